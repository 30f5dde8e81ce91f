// The tuning panels: an edit is validated and pushed on the undo stack; the panels show the world's settings
// and the selected part's stability advice.
#include "vaw/ui/main_window.hpp"

#include <QLabel>
#include <QStatusBar>
#include <QUndoStack>
#include <type_traits>
#include <variant>

#include "vaw/sim/edit.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/work_precision_dock.hpp"

namespace vaw::ui {

void MainWindow::wireTuning() {
  // The tuning panels ask; the undo stack and the simulation's queue do.
  connect(gravityDock_, &GravityDock::editRequested, this, &MainWindow::requestTuning);
  connect(methodsDock_, &MethodsDock::editRequested, this, &MainWindow::requestTuning);
  connect(frictionDock_->model(), &FrictionModel::editRequested, this,
          [this](const vaw::sim::Edit& e) { requestTuning(e, -1); });
  connect(frictionDock_->model(), &FrictionModel::refused, this, [this](const QString& rule) {
    statusBar()->showMessage(tr("Refused: %1").arg(rule), 10000);
  });
  connect(undoStack_, &QUndoStack::cleanChanged, this, &MainWindow::updateTitle);
}

void MainWindow::requestTuning(const vaw::sim::Edit& edit, int mergeKey) {
  if (!simulation_->hasWorld()) return;
  const vaw::sim::World& w = simulation_->world();
  const std::string problem = vaw::sim::validate(edit, w.assembly());
  if (!problem.empty()) {
    const QString text = tr("Refused: %1").arg(QString::fromStdString(problem));
    message(static_cast<int>(MessageLogModel::Severity::Warning), text);
    statusBar()->showMessage(text, 10000);
    updateLive();  // the panel shows the value kept
    return;
  }
  // What the world has now, as a whole value of the same kind: undo sends it back.
  const vaw::sim::Edit before = std::visit(
      [&w](const auto& e) -> vaw::sim::Edit {
        using E = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<E, vaw::sim::GravityEdit>) return vaw::sim::GravityEdit{w.settings().gravity};
        else if constexpr (std::is_same_v<E, vaw::sim::MaterialFrictionEdit>)
          return vaw::sim::MaterialFrictionEdit{e.material, w.materialFriction(e.material)};
        else if constexpr (std::is_same_v<E, vaw::sim::PartFrictionEdit>) {
          return vaw::sim::PartFrictionEdit{e.part, w.frictionOverride(e.part)};
        } else if constexpr (std::is_same_v<E, vaw::sim::MethodEdit>) return vaw::sim::MethodEdit{w.settings().rotationMethod};
        else return vaw::sim::RateEdit{w.settings().rate};
      },
      edit);
  undoStack_->push(new EditCommand(*simulation_, before, edit, QString::fromStdString(vaw::sim::describe(edit, w.assembly())),
                                   mergeKey));
}

void MainWindow::updateTuning(const std::optional<vaw::sim::StabilityAdvice>& advice) {
  const vaw::sim::World& w = simulation_->world();
  const auto part = simulation_->selected();
  gravityDock_->showWorld(w);
  frictionDock_->model()->showWorld(&w, part);
  const QString name = part ? QString::fromStdString(w.assembly().parts[*part].name) : QString();
  methodsDock_->showWorld(w, advice, name);
  workPrecisionDock_->showWorld(w, part);
  const bool warn = advice && advice->level != vaw::sim::StabilityAdvice::Level::Stable;
  // Whether a rotation method is near its limit depends on the gravity scale: hidden while a blinded trial plays.
  stabilityStatus_->setVisible(warn && !blinded_);
  QString fix;
  if (warn && advice->safeMethod) fix = tr("use %1").arg(QString::fromLatin1(vaw::dyn::name(*advice->safeMethod).data()));
  if (warn && advice->safeRate)
    fix += (fix.isEmpty() ? tr("use ") : tr(" or ")) + tr("%1 Hz").arg(QString::number(*advice->safeRate, 'g', 6));
  stabilityStatus_->setText(
      warn ? tr("⚠ %1: %2 at %3 Hz %4%5")
                 .arg(name, QString::fromLatin1(vaw::dyn::name(w.settings().rotationMethod).data()),
                      QString::number(w.settings().rate, 'g', 6),
                      advice->level == vaw::sim::StabilityAdvice::Level::Unstable ? tr("is unstable") : tr("is near its limit"),
                      fix.isEmpty() ? QString() : QStringLiteral(" (%1)").arg(fix))
           : QString());
  stabilityStatus_->setToolTip(warn ? QString::fromStdString(advice->text) : QString());
}

}  // namespace vaw::ui
