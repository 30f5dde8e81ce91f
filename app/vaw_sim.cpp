// vaw-sim: the headless runner. `inspect` prints what vaw makes of a scene: per part its mass
// properties and lifting category, with the reason, and how each constraint meets the base.
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_command.hpp"
#include "trials_command.hpp"
#include "work_precision_command.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/interaction/states.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/version.hpp"

namespace {

constexpr const char* kUsage =
    "usage: vaw-sim inspect SCENE [--json] [--categories default|stricter]\n"
    "       vaw-sim work-precision --out DIR [--repeats N] [--no-peers]\n"
    "       vaw-sim states [--dot]\n"
    "       vaw-sim run SCENE --inputs SCRIPT --out DIR | run --replay SESSION --out DIR\n"
    "       vaw-sim trials simulate|analyze|demand ...   (vaw-sim trials --help)\n"
    "\n"
    "  inspect    load a scene (or a bare mesh file) and print, per part: name, mass, volume,\n"
    "             centre of mass, principal moments, category and why; per constraint, how it meets\n"
    "             the base (a bore on a shaft: both radii and the clearance)\n"
    "  --json     print JSON instead of a table\n"
    "  --categories PRESET   lifting thresholds: default (NIOSH/HSE men) or stricter (HSE women)\n"
    "  work-precision  run every scenario (slide with stop, gear pendulum undamped and damped,\n"
    "             tumbling block) with every method at 30..1000 Hz, and the Bullet/ODE peers when\n"
    "             built; write DIR/work-precision.csv and one chart per scenario (PNG and SVG)\n"
    "  states     print the part-state transition table (--dot: as Graphviz, docs/states.dot)\n"
    "  run        simulate SCENE headless over an input script (docs/inputs-format.md) or a recorded\n"
    "             session; write DIR/trajectories.csv, DIR/transitions.csv, DIR/session.vaw-session.json\n"
    "  trials     gravity-scale trials: simulate a design against a simulated participant, analyse\n"
    "             results files (PSE with interval, chart), the head-demand model (docs/trials.md)\n"
    "\n"
    "exit status: 0 ok, 1 bad input (the message names file, field and expectation), 2 usage\n";

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json toJson(const vaw::Assembly& a, const std::vector<vaw::collision::ConstraintFit>& fits) {
  nlohmann::json parts = nlohmann::json::array();
  for (const auto& p : a.parts) {
    nlohmann::json j{{"name", p.name},
                     {"mass_kg", p.mass.mass},
                     {"volume_m3", p.mass.volume},
                     {"center_of_mass_m", vec(p.mass.centerOfMass)},
                     {"principal_moments_kg_m2", vec(p.principal.moments)},
                     {"extent_m", p.extent},
                     {"category", std::string(vaw::name(p.category.category))},
                     {"category_reason", p.category.reason},
                     {"mass_source", p.massSource == vaw::MassSource::PropertyFile ? "property file" : "mesh"},
                     {"triangles", p.mesh->triangleCount()},
                     {"material", p.material},
                     {"is_base", a.base && *a.base == p.id}};
    if (p.disagreement)
      j["disagreement"] = {{"mass_rel", p.disagreement->massRel},
                           {"com_m", p.disagreement->comDistance},
                           {"inertia_rel", p.disagreement->inertiaRel}};
    parts.push_back(std::move(j));
  }
  nlohmann::json fitList = nlohmann::json::array();
  for (const auto& f : fits) {
    const vaw::Constraint& c = a.constraints[f.constraint];
    nlohmann::json j{{"constraint", c.name},
                     {"type", std::string(vaw::name(c.type))},
                     {"part", a.parts[c.part].name},
                     {"ok", f.support.problem.empty()},
                     {"fit", f.text}};
    if (f.support.kind == vaw::collision::Support::Kind::Axis && f.support.problem.empty())
      j["clearance_m"] = f.support.clearance;
    fitList.push_back(std::move(j));
  }
  nlohmann::json warnings = nlohmann::json::array();
  for (const auto& w : a.warnings) warnings.push_back(w.message());
  return {{"name", a.name},
          {"source", a.source.string()},
          {"units", std::string(vaw::name(a.units))},
          {"category_preset", a.categorySettings.preset},
          {"parts", parts},
          {"environment", a.environment.size()},
          {"constraints", a.constraints.size()},
          {"fits", fitList},
          {"triangles", a.totalTriangles()},
          {"warnings", warnings}};
}

void printTable(const vaw::Assembly& a, const std::vector<vaw::collision::ConstraintFit>& fits) {
  std::printf("%s (%s): %zu parts, %zu environment objects, %zu constraints, %zu triangles; categories: %s\n",
              a.name.c_str(), a.source.string().c_str(), a.parts.size(), a.environment.size(), a.constraints.size(),
              a.totalTriangles(), a.categorySettings.preset.c_str());
  std::printf("%-18s %10s %12s %26s %32s %-11s %s\n", "part", "mass kg", "volume cm^3", "centre of mass mm",
              "principal moments kg m^2", "category", "why");
  for (const auto& p : a.parts) {
    const auto& c = p.mass.centerOfMass;
    const auto& m = p.principal.moments;
    char com[64], mom[64];
    std::snprintf(com, sizeof com, "(%.2f, %.2f, %.2f)", 1e3 * c.x(), 1e3 * c.y(), 1e3 * c.z());
    std::snprintf(mom, sizeof mom, "%.3e %.3e %.3e", m.x(), m.y(), m.z());
    std::string name = p.name + (a.base && *a.base == p.id ? " [base]" : "");
    std::printf("%-18s %10.4f %12.3f %26s %32s %-11s %s\n", name.c_str(), p.mass.mass, 1e6 * p.mass.volume, com, mom,
                std::string(vaw::name(p.category.category)).c_str(), p.category.reason.c_str());
    if (p.disagreement)
      std::printf("%-18s property file vs mesh: mass %.3f %%, centre of mass %.3f mm, inertia %.3f %%\n", "",
                  100.0 * p.disagreement->massRel, 1e3 * p.disagreement->comDistance, 100.0 * p.disagreement->inertiaRel);
  }
  for (const auto& f : fits) {
    const vaw::Constraint& c = a.constraints[f.constraint];
    std::printf("constraint %s (%s): %s\n", c.name.c_str(), a.parts[c.part].name.c_str(), f.text.c_str());
  }
  for (const auto& w : a.warnings) std::printf("warning: %s\n", w.message().c_str());
}

int inspect(const std::vector<std::string>& args) {
  std::string file;
  bool json = false;
  vaw::LoadOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--json") json = true;
    else if (args[i] == "--categories" && i + 1 < args.size()) {
      if (!vaw::CategorySettings::byName(args[++i], options.categories)) {
        std::fprintf(stderr, "vaw-sim: unknown category preset \"%s\" (default, stricter)\n", args[i].c_str());
        return 2;
      }
    } else if (!args[i].empty() && args[i][0] == '-') {
      std::fprintf(stderr, "vaw-sim: unknown option %s\n%s", args[i].c_str(), kUsage);
      return 2;
    } else if (file.empty()) file = args[i];
    else {
      std::fprintf(stderr, "vaw-sim: one scene at a time\n%s", kUsage);
      return 2;
    }
  }
  if (file.empty()) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  vaw::ImporterRegistry importers;
  for (const auto& dir : vaw::ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  // A large file takes seconds: say how far it is, on a terminal, at most every whole percent.
  const bool tty = isatty(STDERR_FILENO) != 0;
  int shown = -1;
  const vaw::ProgressFn progress = [tty, &shown](double fraction, const std::string& stage) {
    const int percent = static_cast<int>(fraction * 100.0);
    if (tty && percent != shown) {
      shown = percent;
      std::fprintf(stderr, "\rvaw-sim: loading %3d %% %-40.40s", percent, stage.c_str());
    }
    return true;
  };
  try {
    const vaw::Assembly a = vaw::loadAny(vaw::resolveScenePath(file), importers, options, progress);
    if (tty) std::fprintf(stderr, "\r%70s\r", "");
    // How each constraint meets the base (the fit's clearance, or why it does not fit): surface patches
    // of the constrained parts only.
    const auto fits = vaw::collision::constraintFits(a);
    if (json) std::cout << toJson(a, fits).dump(2) << '\n';
    else printTable(a, fits);
    return 0;
  } catch (const vaw::InputError& e) {
    if (tty) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

int dispatch(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fprintf(args.empty() ? stderr : stdout, "%s", kUsage);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::printf("vaw-sim %s\n", vaw::kVersion);
    return 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  // A subcommand's --help is a request for its usage, not a mistake in its arguments (trials has its own).
  if (command != "trials" && std::find(args.begin(), args.end(), "--help") != args.end()) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command == "inspect") return inspect(args);
  if (command == "states") {
    const bool dot = !args.empty() && args[0] == "--dot";
    if (args.size() > (dot ? 1u : 0u)) {
      std::fprintf(stderr, "%s", kUsage);
      return 2;
    }
    std::fputs((dot ? vaw::interact::tableDot() : vaw::interact::tableText()).c_str(), stdout);
    return 0;
  }
  if (command == "run") return vaw::app::run(args);
  if (command == "trials") return vaw::app::trials(args, argc, argv);
  if (command == "work-precision") return vaw::app::workPrecision(args, argc, argv);
  std::fprintf(stderr, "vaw-sim: unknown command \"%s\"\n%s", command.c_str(), kUsage);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit then fails the write (EFBIG), which is reported, instead of killing the process
  // with a half-written file.
  std::signal(SIGXFSZ, SIG_IGN);
  // Every failure ends as a named error and exit status 1; nothing aborts.
  try {
    return dispatch(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "vaw-sim: error: out of memory\n");
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "vaw-sim: error: file system: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
  }
  return 1;
}
