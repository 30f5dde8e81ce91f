// The window's memory over a long session, as a person uses it: the bundled gearbox open, a part grabbed,
// carried and thrown every 15 s of session, the base tilted and turned in the Base panel now and then, Reset
// (Ctrl+R) every 60 throws. The simulation runs at 2x so that a 30-minute soak is an hour of session.
//
// It writes one row per throw (wall and session time, resident and heap memory) to a CSV file and prints
// the growth of the resident memory per hour of session between resets, from a least-squares line over
// each span between resets (the first minute of each left out: the world's snapshots and the views settle).
// tests/soak/soak.sh runs it under Xvfb; docs/benchmarks.md has the results.
//
// Environment: VAW_SOAK_MINUTES (wall minutes, default 30), VAW_SOAK_SPEED (default 2),
// VAW_SOAK_THROW_EVERY (session seconds, default 15), VAW_SOAK_THROWS_PER_RESET (default 60), VAW_SOAK_THROWS
// (stop after that many throws, within the minutes; default: no such limit), VAW_SOAK_CSV (default soak.csv in the working directory),
// VAW_SOAK_MAX_MB_PER_HOUR (fail above it; default none).
#include <malloc.h>

#include <Qt3DExtras/Qt3DWindow>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFile>
#include <QRandomGenerator>
#include <QSignalSpy>
#include <QTextStream>
#include <QtTest>
#include <algorithm>
#include <array>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "../gui/gui_test_support.hpp"
#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

namespace {

// A setting from the environment: `fallback` when unset; a value that is not a number of at least 0 ends the
// soak at once, named, rather than running half an hour on the default.
double envNumber(const char* name, double fallback) {
  if (!qEnvironmentVariableIsSet(name)) return fallback;
  const QString text = qEnvironmentVariable(name);
  bool ok = false;
  const double v = text.toDouble(&ok);
  if (!ok || !(v >= 0.0)) qFatal("%s: expected a number of at least 0, found \"%s\"", name, qPrintable(text));
  return v;
}

// Resident memory of this process (VmRSS), MB.
double residentMb() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = 0.0;
      in >> kb;
      return kb / 1024.0;
    }
    in.ignore(4096, '\n');
  }
  return 0.0;
}

// What the program holds on malloc's heap (live allocations), MB: grows with data, not with fragmentation.
double heapMb() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

struct Row {
  double wall = 0.0, session = 0.0, rss = 0.0, heap = 0.0, recording = 0.0;
  int throws = 0, resets = 0, resetAt = 0;
};

// Least-squares slope of y over x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  const double d = n * sxx - sx * sx;
  return d > 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

}  // namespace

class SoakWindow : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
    // Qt Test's watchdog ends a test function after 5 minutes: the soak is one, as long as asked.
    const double ms = (envNumber("VAW_SOAK_MINUTES", 30.0) + 5.0) * 60000.0;
    qputenv("QTEST_FUNCTION_TIMEOUT", QByteArray::number(static_cast<qint64>(ms)));
  }

 private slots:
  void initTestCase() { QVERIFY(bench_.start()); }
  void cleanupTestCase() { bench_.stop(); }
  void soak();

 private:
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return bench_.window->simulation(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *bench_.controller->assembly(); }
  bool throwOnePart(QRandomGenerator& random);
  void moveTheBase(QRandomGenerator& random);

  vaw::guitest::Workbench bench_;
};

// A one-hand part the viewport shows, taken with a press and a drag, held a moment, then flicked sideways
// and let go while the mouse still moves. False when no part could be taken (all out of sight).
bool SoakWindow::throwOnePart(QRandomGenerator& random) {
  vaw::ui::Viewport* viewport = bench_.window->viewport();
  std::vector<vaw::PartId> candidates;
  for (const auto& p : assembly().parts)
    if (p.id != assembly().base && p.category.category == vaw::Category::OneHand) candidates.push_back(p.id);
  std::shuffle(candidates.begin(), candidates.end(), random);
  QWindow* view = viewport->view3d();
  for (const vaw::PartId part : candidates) {
    const auto state = sim().world().part(part).state;
    if (state != vaw::interact::PartState::Static && state != vaw::interact::PartState::OnBaseStatic) continue;
    const QPoint p = vaw::guitest::pointOnPart(viewport, assembly(), part, sim().world().part(part).pose);
    if (p.x() < 0) continue;
    // Just past the drag distance, where the hand closes; the world takes the part on its next step with the
    // hand where it is then, so the carry waits for that (at the home view's scale a few pixels are
    // centimetres, out of the hand's reach).
    vaw::guitest::pressAndDrag(view, p, p + QPoint(0, -12), 2, 30);
    if (QTest::qWaitFor([&] { return sim().world().part(part).state == vaw::interact::PartState::InHand; }, 3000))
      for (int i = 1; i <= 4; ++i) {
        QTest::mouseMove(view, p + QPoint(0, -12 - 7 * i));
        QTest::qWait(30);
      }
    if (!QTest::qWaitFor([&] { return sim().world().part(part).state == vaw::interact::PartState::InHand; }, 3000)) {
      QTest::mouseRelease(view, Qt::LeftButton, {}, p + QPoint(0, -40));
      continue;
    }
    QTest::qWait(400);  // carried a moment
    QPoint at = p + QPoint(0, -40);
    // Sideways towards the middle of the view, so that the flick stays in it.
    const int room = at.x() > view->width() / 2 ? at.x() - 10 : view->width() - 10 - at.x();
    const int dx = (at.x() > view->width() / 2 ? -1 : 1) * std::clamp(room / 10, 1, 15);
    for (int i = 0; i < 10; ++i) {
      at += QPoint(dx, at.y() > 20 ? -1 : 0);
      QTest::mouseMove(view, at);
      QTest::qWait(12);
    }
    QTest::mouseRelease(view, Qt::LeftButton, {}, at);
    return true;
  }
  return false;
}

// The base tilted or turned in the Base panel, as a person types an angle; back to level half of the time.
void SoakWindow::moveTheBase(QRandomGenerator& random) {
  auto* controls = bench_.window->controlsDock();
  QDoubleSpinBox* box = std::array{controls->tiltX(), controls->tiltY(), controls->turn()}[random.bounded(3)];
  const double angle = random.bounded(2) == 0 ? 0.0 : static_cast<double>(random.bounded(-12, 13));
  vaw::guitest::typeInto(box, QString::number(angle));
}

void SoakWindow::soak() {
  const double minutes = envNumber("VAW_SOAK_MINUTES", 30.0);
  const double speed = envNumber("VAW_SOAK_SPEED", 2.0);
  const int throwsPerReset = static_cast<int>(envNumber("VAW_SOAK_THROWS_PER_RESET", 60.0));
  const double throwEvery = envNumber("VAW_SOAK_THROW_EVERY", 15.0);
  const int throwsWanted = static_cast<int>(envNumber("VAW_SOAK_THROWS", 0.0));  // 0: as many as fit
  const double maxGrowth = envNumber("VAW_SOAK_MAX_MB_PER_HOUR", -1.0);
  const QString csvPath = qEnvironmentVariable("VAW_SOAK_CSV", QStringLiteral("soak.csv"));
  QVERIFY(bench_.open(QFile::decodeName((vaw::resourceDir() / "scenes" / "large-gearbox.vaw.json").string().c_str())));
  sim().setSpeed(speed);
  if (!sim().isPlaying()) sim().play();

  QFile csv(csvPath);
  QVERIFY2(csv.open(QIODevice::WriteOnly | QIODevice::Truncate | QIODevice::Text), qPrintable(csvPath));
  QTextStream out(&csv);
  out << "wall_s,session_s,rss_mb,heap_mb,recording_mb,throws,resets\n";

  QRandomGenerator random(20261127);
  QElapsedTimer wall;
  wall.start();
  std::vector<Row> rows;
  int throws = 0, resets = 0, resetAt = 0;
  double sessionBeforeReset = 0.0;  // session time of earlier resets' recordings
  const auto record = [&] {
    Row r{static_cast<double>(wall.elapsed()) / 1000.0, sessionBeforeReset + sim().world().time(), residentMb(), heapMb(),
          static_cast<double>(sim().recorder().memoryBytes()) / (1024.0 * 1024.0), throws, resets};
    rows.push_back(r);
    out << r.wall << ',' << r.session << ',' << r.rss << ',' << r.heap << ',' << r.recording << ',' << r.throws << ',' << r.resets << '\n';
    out.flush();
  };
  record();
  while (static_cast<double>(wall.elapsed()) < minutes * 60000.0 && (throwsWanted == 0 || throws < throwsWanted)) {
    const double next = sim().world().time() + throwEvery;
    QVERIFY(QTest::qWaitFor([&] { return sim().world().time() >= next; }, static_cast<int>(5000.0 + 4000.0 * throwEvery / speed)));
    if (throwOnePart(random)) ++throws;
    if (throws % 7 == 3) moveTheBase(random);
    record();
    if (throws - resetAt >= throwsPerReset) {
      resetAt = throws;
      sessionBeforeReset += sim().world().time();
      vaw::guitest::pressKey(bench_.window.get(), Qt::Key_R, Qt::ControlModifier);
      QVERIFY(QTest::qWaitFor([&] { return sim().world().time() < 1.0; }, 5000));
      if (!sim().isPlaying()) sim().play();
      ++resets;
      record();
    }
    vaw::guitest::verifyNoWarnings();
  }

  // Growth per hour of session within each span between resets (leaving out its first minute), weighted by
  // the spans' lengths, and the steepest span.
  struct Growth {
    double mean = 0.0, worst = 0.0;
    QStringList spans;
  };
  const auto growth = [&](double Row::*value) {
    Growth g;
    double total = 0.0, hours = 0.0;
    for (int span = 0; span <= resets; ++span) {
      std::vector<double> t, y;
      double start = -1.0;
      for (const Row& r : rows) {
        if (r.resets != span) continue;
        if (start < 0.0) start = r.session;
        if (r.session - start < 60.0) continue;
        t.push_back(r.session / 3600.0);
        y.push_back(r.*value);
      }
      if (t.size() < 5) continue;
      const double s = slope(t, y);
      const double h = t.back() - t.front();
      g.spans << QStringLiteral("%1 over %2 min").arg(s, 0, 'f', 1).arg(h * 60.0, 0, 'f', 1);
      g.worst = std::max(g.worst, s);
      total += s * h;
      hours += h;
    }
    g.mean = hours > 0.0 ? total / hours : 0.0;
    return g;
  };
  const Growth rss = growth(&Row::rss), heap = growth(&Row::heap), recording = growth(&Row::recording);
  std::printf("soak: %.1f min wall, %.1f min of session, %d throws, %d resets; RSS %.0f -> %.0f MB, heap %.0f -> %.0f MB\n",
              rows.back().wall / 60.0, rows.back().session / 60.0, throws, resets, rows.front().rss, rows.back().rss,
              rows.front().heap, rows.back().heap);
  std::printf("soak: growth between resets, MB per hour of session: resident %.1f (worst span %.1f; spans: %s), heap %.1f, "
              "of which the recording %.1f; rows in %s\n",
              rss.mean, rss.worst, qPrintable(rss.spans.join(QStringLiteral(", "))), heap.mean, recording.mean, qPrintable(csvPath));
  std::fflush(stdout);
  QVERIFY2(throws > 0, "no part could be thrown");
  if (maxGrowth >= 0.0) QVERIFY2(rss.mean <= maxGrowth, qPrintable(QStringLiteral("%1 MB/h > %2").arg(rss.mean).arg(maxGrowth)));
}

QTEST_MAIN(SoakWindow)
#include "soak_window.moc"
