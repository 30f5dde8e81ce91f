#pragma once
// "Path": the space the selected part's carried path needs and how close it came to everything else, over
// the recording (docs/swept-volume.md, docs/clearance.md). Sweep works in the background on a copy of the
// session: the swept volume (drawn translucent in the viewport, its volume and voxel in the panel) and the
// clearance at every step (charted over time with the near-miss threshold, and a table of the objects by
// their least clearance; activating a row shows that moment on the timeline). Export writes the volume in
// the scene's unit and frame: binary STL, or a STEP solid through the STEP plugin (in the background).
#include <QDockWidget>
#include <QFutureWatcher>
#include <QString>
#include <atomic>
#include <memory>
#include <optional>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/swept_volume.hpp"

class QCheckBox;
class QChartView;
class QDoubleSpinBox;
class QLabel;
class QLineSeries;
class QScatterSeries;
class QProgressBar;
class QPushButton;
class QStandardItemModel;
class QTableView;
class QValueAxis;

namespace vaw::ui {

class SimulationController;
class Viewport;

class PathDock : public QDockWidget {
  Q_OBJECT
 public:
  PathDock(SimulationController& simulation, Viewport& viewport, const vaw::ImporterRegistry& plugins, QWidget* parent = nullptr);
  ~PathDock() override;
  PathDock(const PathDock&) = delete;
  PathDock& operator=(const PathDock&) = delete;

  [[nodiscard]] QPushButton* sweepButton() const { return sweep_; }
  [[nodiscard]] QPushButton* exportButton() const { return export_; }
  [[nodiscard]] QPushButton* stopExportButton() const { return stopExport_; }
  [[nodiscard]] QDoubleSpinBox* voxelBox() const { return voxel_; }
  [[nodiscard]] QDoubleSpinBox* thresholdBox() const { return threshold_; }
  [[nodiscard]] QCheckBox* relativeBox() const { return relative_; }
  [[nodiscard]] QCheckBox* showBox() const { return show_; }
  [[nodiscard]] QLabel* summary() const { return summary_; }
  [[nodiscard]] QTableView* table() const { return table_; }
  [[nodiscard]] QChartView* chartView() const { return chartView_; }
  [[nodiscard]] QLineSeries* distanceSeries() const { return distance_; }
  [[nodiscard]] QScatterSeries* nearSeries() const { return near_; }
  [[nodiscard]] bool working() const { return working_; }
  // The last result, for the part it was computed for (none before the first, or after a new scene).
  [[nodiscard]] const vaw::SweptVolume* swept() const { return result_ ? &result_->swept : nullptr; }
  [[nodiscard]] const vaw::sim::ClearanceReport* clearance() const { return result_ ? &result_->clearance : nullptr; }
  [[nodiscard]] std::optional<vaw::PartId> resultPart() const { return result_ ? std::optional(result_->part) : std::nullopt; }

 public slots:
  void setPart(std::optional<vaw::PartId> part);
  // Computes for the selected part over the recording so far.
  void sweep();
  // Writes the swept volume to `file`: binary STL (.stl), or a STEP solid (.step, .stp) when a plugin
  // writes STEP, in the background, within the STEP settings' time and memory limits, its progress in the
  // panel and Stop beside it; `faceted`: a faceted STEP B-rep (vaw::ExportOptions::faceted). Emits
  // exported(file, why): `why` empty when it was written.
  void exportVolume(const QString& file, bool faceted = false);
  // Stops the write under way; nothing is left at its file but what was there.
  void stopExport();
  [[nodiscard]] bool exporting() const { return exporting_; }
  // A new world (scene, reset, session): the last result no longer belongs to it.
  void clear();

 signals:
  void finishedSweep();
  void cleared();  // the last result is gone (a new world)
  void exported(const QString& file, const QString& why);
  void statusMessage(const QString& text);

 private:
  struct Result {
    std::shared_ptr<const vaw::sim::Scene> scene;
    vaw::PartId part = 0;
    vaw::SweptVolume swept;
    vaw::sim::ClearanceReport clearance;
    QString error;
    unsigned generation = 0;  // the world it was computed in
  };
  void finished();
  void showResult();
  void showThreshold();
  void askExport();

  SimulationController& simulation_;
  Viewport& viewport_;
  const vaw::ImporterRegistry& plugins_;
  bool exporting_ = false;
  QFutureWatcher<QString> exportWatcher_;  // the reason a write failed, empty when it did not
  QString exportFile_;
  std::shared_ptr<std::atomic<bool>> exportStopped_;  // asked by the write under way
  std::optional<vaw::PartId> part_;
  std::optional<Result> result_;
  bool working_ = false;
  unsigned generation_ = 0;  // counts new worlds
  QFutureWatcher<Result> watcher_;
  QLabel* partLabel_ = nullptr;
  QDoubleSpinBox* voxel_ = nullptr;
  QDoubleSpinBox* threshold_ = nullptr;
  QCheckBox* relative_ = nullptr;
  QCheckBox* show_ = nullptr;
  QPushButton* sweep_ = nullptr;
  QPushButton* export_ = nullptr;
  QPushButton* stopExport_ = nullptr;
  QProgressBar* busy_ = nullptr;
  QLabel* summary_ = nullptr;
  QTableView* table_ = nullptr;
  QStandardItemModel* rows_ = nullptr;
  QChartView* chartView_ = nullptr;
  QLineSeries* distance_ = nullptr;
  QLineSeries* limit_ = nullptr;
  QScatterSeries* near_ = nullptr;
  QValueAxis* timeAxis_ = nullptr;
  QValueAxis* distanceAxis_ = nullptr;
};

}  // namespace vaw::ui
