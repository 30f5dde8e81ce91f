// vaw-sim: the headless runner. The command line is parsed by CLI11 (one parser for every subcommand, so
// --help, --version and the usage errors behave alike); `inspect` prints what vaw makes of a scene: per
// part its mass properties and lifting category, with the reason, and how each constraint meets the base.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluate_command.hpp"
#include "export_command.hpp"
#ifdef VAW_HAVE_VIDEO
#include "video_command.hpp"
#endif
#include "clearance_command.hpp"
#include "run_command.hpp"
#include "trials_command.hpp"
#include "work_precision_command.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/interaction/states.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/version.hpp"

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

const char* massSource(vaw::MassSource s) {
  switch (s) {
    case vaw::MassSource::PropertyFile: return "property file";
    case vaw::MassSource::Brep: return "B-rep";
    case vaw::MassSource::Mesh: break;
  }
  return "mesh";
}

std::string partnerName(const vaw::Assembly& a, const vaw::Constraint& c) {
  const auto partner = c.partner ? c.partner : a.base;
  return partner ? a.parts[*partner].name : std::string("(none)");
}

nlohmann::json interferenceJson(const vaw::Assembly& a, const std::vector<vaw::collision::Interference>& found) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& i : found) {
    nlohmann::json j{{"kind", std::string(vaw::collision::name(i.kind))},
                     {"parts", {a.parts[i.a].name, a.parts[i.b].name}},
                     {"volume_m3", i.volume},
                     {"depth_m", i.depth}};
    if (i.kind != vaw::collision::Interference::Kind::Contact) {
      j["where_m"] = vec(i.where);
      j["direction"] = vec(i.direction);
    }
    if (!i.thread.empty()) j["thread"] = i.thread;
    out.push_back(std::move(j));
  }
  return out;
}

nlohmann::json nearMissJson(const vaw::Assembly& a, const std::vector<vaw::NearMiss>& misses) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& m : misses)
    out.push_back({{"parts", {a.parts[m.a].name, a.parts[m.b].name}}, {"type", std::string(vaw::name(m.type))}, {"why", m.why},
                   {"measured", m.value}, {"limit", m.limit}});
  return out;
}

void printNearMisses(const vaw::Assembly& a, const std::vector<vaw::NearMiss>& misses) {
  std::printf("near misses (faces that look like a fit and were not taken): %zu\n", misses.size());
  for (const auto& m : misses)
    std::printf("near miss %s: %s and %s: %s\n", std::string(vaw::name(m.type)).c_str(), a.parts[m.a].name.c_str(), a.parts[m.b].name.c_str(),
                m.why.c_str());
}

// "13 threaded, 1 clash, 96 contacts", then a line per designed fit and clash.
void printInterferences(const vaw::Assembly& a, const std::vector<vaw::collision::Interference>& found) {
  using Kind = vaw::collision::Interference::Kind;
  std::size_t count[4] = {0, 0, 0, 0};
  for (const auto& i : found) ++count[static_cast<int>(i.kind)];
  std::printf("interferences at rest: %zu clash%s, %zu threaded, %zu press, %zu touching\n", count[static_cast<int>(Kind::Clash)],
              count[static_cast<int>(Kind::Clash)] == 1 ? "" : "es", count[static_cast<int>(Kind::Threaded)], count[static_cast<int>(Kind::Press)],
              count[static_cast<int>(Kind::Contact)]);
  for (const auto& i : found) {
    if (i.kind == Kind::Contact) continue;
    const std::string what = i.kind == Kind::Threaded ? "threaded " + i.thread : std::string(vaw::collision::name(i.kind));
    std::printf("interference %s: %s and %s, %.3f mm^3, %.3f mm deep, at (%.2f, %.2f, %.2f) mm\n", what.c_str(), a.parts[i.a].name.c_str(),
                a.parts[i.b].name.c_str(), 1e9 * i.volume, 1e3 * i.depth, 1e3 * i.where.x(), 1e3 * i.where.y(), 1e3 * i.where.z());
  }
}

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
                     {"mass_source", massSource(p.massSource)},
                     {"triangles", p.mesh->triangleCount()},
                     {"product", p.product},
                     {"material", p.material},
                     {"is_base", a.base && *a.base == p.id}};
    if (!p.unitMembers.empty()) j["unit"] = {{"members", p.unitMembers}, {"reason", p.unitReason}};
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
                     {"partner", partnerName(a, c)},
                     {"ok", f.support.problem.empty()},
                     {"fit", f.text}};
    if (c.found) {
      j["found"] = {{"clearance_m", c.found->clearance}, {"overlap", c.found->overlap}, {"from_spline", c.found->fromSpline}};
      if (c.type == vaw::Constraint::Type::Insert) {
        j["found"]["part_radius_m"] = c.found->partRadius;
        j["found"]["partner_radius_m"] = c.found->partnerRadius;
        j["found"]["fit"] = std::string(vaw::name(c.found->fit));
        if (!c.found->thread.empty()) j["found"]["thread"] = c.found->thread;
        if (c.found->seat != vaw::Constraint::Found::Seat::None) {
          j["found"]["seat"] = std::string(vaw::name(c.found->seat));
          j["found"]["seat_radius_m"] = c.found->seatRadius;
          if (c.found->seat == vaw::Constraint::Found::Seat::Countersink) j["found"]["seat_half_angle_rad"] = c.found->seatAngle;
        }
      } else if (c.found->keyWidth > 0.0) {
        j["found"]["key_width_m"] = c.found->keyWidth;
      }
    }
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
          {"up", {{"choice", a.cadUp}, {"file_axis", {a.cadUpAxis.x(), a.cadUpAxis.y(), a.cadUpAxis.z()}}}},
          {"base", {{"part", a.base ? a.parts[*a.base].name : std::string()}, {"reason", a.baseReason}}},
          {"warnings", warnings}};
}

// "+y" for a file axis, else the components.
std::string axisText(const Eigen::Vector3d& v) {
  const char* names[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(v[i]) - 1.0) < 1e-9) return std::string(v[i] > 0 ? "+" : "-") + names[i];
  char buf[80];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
  return buf;
}

void printTable(const vaw::Assembly& a, const std::vector<vaw::collision::ConstraintFit>& fits) {
  std::printf("%s (%s): %zu parts, %zu environment objects, %zu constraints, %zu triangles; categories: %s\n",
              a.name.c_str(), a.source.string().c_str(), a.parts.size(), a.environment.size(), a.constraints.size(),
              a.totalTriangles(), a.categorySettings.preset.c_str());
  if (!a.cadFile.empty())
    std::printf("stands with the file's %s up (%s)\n", axisText(a.cadUpAxis).c_str(),
                a.cadUp == "auto" ? "auto: on the footing of its base" : ("chosen: " + a.cadUp).c_str());
  if (a.base && !a.baseReason.empty()) std::printf("base: %s, %s\n", a.parts[*a.base].name.c_str(), a.baseReason.c_str());
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
    if (!p.unitMembers.empty())
      std::printf("%-18s a unit of %zu parts, handled as one%s%s\n", "", p.unitMembers.size(), p.unitReason.empty() ? "" : ": ",
                  p.unitReason.c_str());
    if (p.disagreement)
      std::printf("%-18s %s vs mesh: mass %.3f %%, centre of mass %.3f mm, inertia %.3f %%\n", "", massSource(p.massSource),
                  100.0 * p.disagreement->massRel, 1e3 * p.disagreement->comDistance, 100.0 * p.disagreement->inertiaRel);
  }
  for (const auto& f : fits) {
    const vaw::Constraint& c = a.constraints[f.constraint];
    // The partner is named when it is another part; onto the base is the paper's case.
    const std::string who = a.parts[c.part].name + (c.partner ? " onto " + partnerName(a, c) : std::string());
    std::printf("constraint %s (%s): %s\n", c.name.c_str(), who.c_str(), f.text.c_str());
    if (c.found)
      std::printf("%-18s found in the geometry: %s %.4f %s, clearance %.4f mm%s\n", "",
                  c.type == vaw::Constraint::Type::Insert ? "axial overlap" : "overlap",
                  c.type == vaw::Constraint::Type::Insert ? 1e3 * c.found->overlap : 1e6 * c.found->overlap,
                  c.type == vaw::Constraint::Type::Insert ? "mm" : "mm^2", 1e3 * c.found->clearance,
                  c.found->fromSpline ? " (a B-spline face recognised)" : "");
  }
  for (const auto& w : a.warnings) std::printf("warning: %s\n", w.message().c_str());
}


void addReaderLimits(CLI::App* cmd, vaw::ImportOptions& limits) {
  cmd->add_option("--timeout", limits.timeoutSeconds, "STEP files: seconds the reader may take (default 300)")
      ->check(CLI::Range(0.01, 86400.0));
  cmd->add_option("--reader-memory", limits.readerMemoryMB, "STEP files: the reader's memory limit in MB (default: half the machine's)")
      ->check(CLI::Range(64.0, 1e7));
  cmd->add_option("--max-instances", limits.maxInstances,
                  "STEP files: part instances a file may declare, its assembly tree expanded (default 10000)")
      ->check(CLI::Range(1.0, 1e9));
  limits.resultCache = vaw::userCacheDir();
  cmd->add_flag_callback(
      "--no-cache", [&limits] { limits.resultCache.clear(); },
      "STEP files: read the file even when it is unchanged since an earlier read (kept in $XDG_CACHE_HOME/vaw, or $VAW_CACHE_DIR)");
}

struct InspectArgs {
  std::string file;
  bool json = false;
  bool timings = false;
  std::string categories = "default";
  std::string up;
  vaw::ImportOptions import;  // STEP files: tessellation and the reader's limits
};

int inspect(const InspectArgs& args) {
  vaw::LoadOptions options;
  options.import = args.import;
  if (!args.up.empty()) options.cadUp = args.up;
  if (!vaw::CategorySettings::byName(args.categories, options.categories)) return 2;  // the parser allows known names only
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
  std::vector<std::pair<std::string, double>> timings;
  if (args.timings) options.timings = &timings;
  try {
    const vaw::Assembly a = vaw::loadAny(vaw::resolveScenePath(args.file), importers, options, progress);
    if (tty) std::fprintf(stderr, "\r%70s\r", "");
    // How each constraint meets the base (the fit's clearance, or why it does not fit): surface patches
    // of the constrained parts only.
    const auto fits = vaw::collision::constraintFits(a);
    // What overlaps at rest, for assemblies whose parts come with their assembled poses (CAD files).
    std::vector<vaw::collision::Interference> overlaps;
    const auto checked = std::chrono::steady_clock::now();
    if (!a.cadFile.empty()) overlaps = vaw::collision::interferences(a, vaw::collision::assembledPoses(a));
    if (args.timings) timings.emplace_back("interferences at rest", std::chrono::duration<double>(std::chrono::steady_clock::now() - checked).count());
    const std::vector<vaw::NearMiss> misses = vaw::nearMisses(a);
    if (args.json) {
      nlohmann::json j = toJson(a, fits);
      if (!a.cadFile.empty()) {
        j["interferences"] = interferenceJson(a, overlaps);
        j["near_misses"] = nearMissJson(a, misses);
      }
      std::cout << j.dump(2) << '\n';
    } else {
      printTable(a, fits);
      if (!a.cadFile.empty()) {
        printInterferences(a, overlaps);
        printNearMisses(a, misses);
      }
    }
    // On stderr, so that the table and the JSON stay what they are.
    for (const auto& [stage, seconds] : timings) std::fprintf(stderr, "time: %-36s %8.3f s\n", stage.c_str(), seconds);
    return 0;
  } catch (const vaw::InputError& e) {
    if (tty) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

// A whole number within [lo, hi], strictly: "abc", "-5" and "3x" are refused, not read as 0 or 1.
CLI::Validator wholeNumber(int lo, int hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 9 && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits && std::stoi(text) >= lo && std::stoi(text) <= hi) return {};
        return "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", found \"" + text + "\"";
      },
      "N");
}

// A finite number within [lo, hi] (hi excluded when `openHi`).
CLI::Validator numberIn(double lo, double hi, bool openHi, const std::string& what) {
  return CLI::Validator(
      [lo, hi, openHi, what](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool ok = end != text.c_str() && *end == '\0' && std::isfinite(v) && v >= lo && (openHi ? v < hi : v <= hi);
        return ok ? std::string() : "expected " + what + ", found \"" + text + "\"";
      },
      "X");
}

int dispatch(int argc, char** argv) {
  CLI::App app{"vaw-sim: the Virtual Assembly Workbench without its window: inspect scenes, run and replay\n"
               "simulations, measure the methods' speed against their accuracy, and run gravity-scale trials.",
               "vaw-sim"};
  app.set_version_flag("--version", std::string("vaw-sim ") + vaw::kVersion, "Print the version and exit");
  app.require_subcommand(1);
  app.footer("Exit status: 0 ok, 1 bad input or output (the message names file, field and expectation), 2 usage,\n"
             "3 (evaluate) some part can be put in place by no order.\n"
             "Each command's options: vaw-sim COMMAND --help.");
  std::function<int()> command;

  InspectArgs ins;
  const CLI::Validator upChoice(
      [](const std::string& up) { return vaw::validUpChoice(up) ? std::string() : std::string("expected ") + vaw::kUpChoices; }, "UP");
  CLI::App* inspectCmd = app.add_subcommand(
      "inspect", "Load a scene (or a bare mesh file; a bundled scene by its name) and print, per part: name, mass, "
                 "volume, centre of mass, principal moments, category and why; per constraint, how it meets the base "
                 "(a bore on a shaft: both radii and the clearance).");
  inspectCmd->add_option("SCENE", ins.file, "Scene, mesh file, or bundled scene name")->required();
  inspectCmd->add_flag("--json", ins.json, "Print JSON instead of a table");
  inspectCmd->add_flag("--timings", ins.timings, "CAD files: print on stderr the seconds each stage of the open took");
  inspectCmd->add_option("--categories", ins.categories, "Lifting thresholds: default (NIOSH/HSE men) or stricter (HSE women)")
      ->check(CLI::IsMember({"default", "stricter"}));
  inspectCmd
      ->add_option("--deflection", ins.import.relativeDeflection,
                   "STEP files: the tessellation's chordal deflection as a fraction of each part's size (default 0.001)")
      ->check(CLI::Range(1e-5, 0.1));
  inspectCmd->add_option("--up", ins.up, "CAD files: which way the assembly stands: auto (the base on its most stable face, "
                                         "the default), the file's axis that points up (+x, -x, +y, -y, +z, -z) or the file's "
                                         "direction that points up as three numbers (\"0 0.6 0.8\")")
      ->check(upChoice);
  addReaderLimits(inspectCmd, ins.import);
  inspectCmd->callback([&] { command = [&] { return inspect(ins); }; });

  bool dot = false;
  CLI::App* statesCmd = app.add_subcommand("states", "Print the part-state transition table.");
  statesCmd->add_flag("--dot", dot, "As Graphviz (docs/states.dot)");
  statesCmd->callback([&] {
    command = [&] {
      std::fputs((dot ? vaw::interact::tableDot() : vaw::interact::tableText()).c_str(), stdout);
      return 0;
    };
  });

  vaw::app::RunArgs run;
  CLI::App* runCmd = app.add_subcommand(
      "run", "Simulate SCENE headless over an input script (docs/inputs-format.md), or replay a recorded session; "
             "write DIR/trajectories.csv, DIR/transitions.csv and DIR/session.vaw-session.json.");
  runCmd->add_option("SCENE", run.scene, "Scene file or bundled scene name (with --replay: overrides the recorded one)");
  CLI::Option* inputsOpt = runCmd->add_option("--inputs", run.inputs, "Input script")->type_name("SCRIPT");
  runCmd->add_option("--replay", run.replay, "Recorded session to replay")->type_name("SESSION")->excludes(inputsOpt);
  runCmd->add_option("--out", run.out, "Output directory")->type_name("DIR")->required();
  runCmd->callback([&] {
    if (run.replay.empty() && (run.scene.empty() || run.inputs.empty()))
      throw CLI::ValidationError("give SCENE --inputs SCRIPT, or --replay SESSION");
    command = [&] { return vaw::app::run(run); };
  });

  vaw::app::ClearanceArgs cl;
  CLI::App* clCmd = app.add_subcommand(
      "clearance", "How close a part's carried path in a recorded session comes to everything else: the nearest object and "
                   "distance at every step, each object's least clearance, near misses, contacts and interference "
                   "(docs/clearance.md); write DIR/clearance.csv and DIR/summary.json.");
  clCmd->add_option("SESSION", cl.session, "Recorded session (.vaw-session.json)")->required();
  clCmd->add_option("--part", cl.part, "The part whose path is measured")->required();
  clCmd->add_option("--from", cl.from, "Start of the span, s (default: every step the part is INHAND or ONTOOL)");
  clCmd->add_option("--to", cl.to, "End of the span, s");
  clCmd->add_option("--threshold", cl.thresholdMm, "Closer than this is a near miss, mm (default 5)")->check(CLI::Range(0.0, 1e6));
  clCmd->add_option("--reach", cl.reachMm, "Objects never this close are left out of the table, mm (default 50)")->check(CLI::Range(0.0, 1e6));
  clCmd->add_option("--out", cl.out, "Output directory")->type_name("DIR")->required();
  clCmd->callback([&] { command = [&] { return vaw::app::clearance(cl); }; });

  vaw::app::SweepArgs sw;
  CLI::App* swCmd = app.add_subcommand(
      "sweep", "The volume a part's carried path in a recorded session sweeps, voxelised so that it holds the whole path, "
               "and the path's clearance (docs/swept-volume.md); given a scene instead, the part's way home from the order "
               "search (docs/evaluation.md). Writes DIR/swept.stl (binary, in the scene's unit and frame), "
               "DIR/swept.step (a solid, through the STEP plugin), DIR/clearance.csv and DIR/summary.json.");
  swCmd->add_option("SESSION_OR_SCENE", sw.clearance.session,
                    "Recorded session (.vaw-session.json), or a scene, STEP or mesh file (or a bundled scene by its name) for a way home")
      ->required();
  swCmd->add_option("--part", sw.clearance.part, "The part whose path is swept")->required();
  swCmd->add_option("--from", sw.clearance.from, "Start of the span, s (default: every step the part is INHAND or ONTOOL)");
  swCmd->add_option("--to", sw.clearance.to, "End of the span, s");
  swCmd->add_option("--voxel", sw.voxelMm, "Voxel edge, mm (default 1)")->check(CLI::Range(1e-3, 1e4));
  swCmd->add_flag("--relative-to-base", sw.relativeToBase, "The path in the base's frame: the space it needs on a base that moves");
  swCmd->add_option("--threshold", sw.clearance.thresholdMm, "Closer than this is a near miss, mm (default 5)")->check(CLI::Range(0.0, 1e6));
  swCmd->add_option("--reach", sw.clearance.reachMm, "Objects never this close are left out of the table, mm (default 50)")->check(CLI::Range(0.0, 1e6));
  swCmd->add_option("--out", sw.clearance.out, "Output directory")->type_name("DIR")->required();
  swCmd->add_option("--step-timeout", sw.step.timeoutSeconds, "Seconds the STEP writer may take (default 300)")->check(CLI::Range(0.01, 86400.0));
  swCmd->add_option("--step-memory", sw.step.memoryMB, "The STEP writer's memory limit in MB (default: half the machine's)")
      ->check(CLI::Range(64.0, 1e7));
  swCmd->add_flag("--step-faceted", sw.step.faceted,
                  "swept.step as a faceted B-rep (faces bounded by loops of points): about a third the size, though some CAD systems "
                  "take it in as a faceted body");
  swCmd->callback([&] { command = [&] { return vaw::app::sweep(sw); }; });

  vaw::app::ExportArgs ex;
  CLI::App* exCmd = app.add_subcommand(
      "export", "The scene and how its parts moved as one glTF 2.0 binary (docs/sharing.md): a recorded session replayed, "
                "or with --order a scene's planned order, each part flying home in its turn; a scene alone at rest.");
  exCmd->add_option("SESSION_OR_SCENE", ex.input, "Recorded session (.vaw-session.json), or a scene, STEP or mesh file")->required();
  exCmd->add_option("--out", ex.out, "The .glb file to write")->type_name("FILE")->required();
  exCmd->add_flag("--order", ex.order, "Play the planned order (a scene, STEP or mesh file)");
  exCmd->add_option("--fps", ex.rate, "Samples a second (default 30)")->check(CLI::Range(1.0, 1000.0));
  exCmd->add_option("--step-seconds", ex.stepSeconds, "Seconds each step of the order takes (default 1)")->check(CLI::Range(0.05, 60.0));
  exCmd->add_option("--tolerance", ex.toleranceMm, "A key is left out where its neighbours come within this, mm (default 0.1; 0 keeps all)")
      ->check(CLI::Range(0.0, 100.0));
  exCmd->callback([&] { command = [&] { return vaw::app::exportGltf(ex); }; });

#ifdef VAW_HAVE_VIDEO
  vaw::app::VideoArgs vi;
  CLI::App* viCmd = app.add_subcommand(
      "video", "A recorded session replayed, or with --order a scene's planned order, as an H.264 video in an MP4 file (docs/sharing.md): "
               "every frame the picture the window would show, with a caption line; no display or GPU needed.");
  viCmd->add_option("SESSION_OR_SCENE", vi.input, "Recorded session (.vaw-session.json), or with --order a scene, STEP or mesh file")->required();
  viCmd->add_option("--out", vi.out, "The .mp4 file to write")->type_name("FILE")->required();
  viCmd->add_option("--size", vi.size, "Picture size in pixels, both even (default 1280x720)")->type_name("WxH");
  viCmd->add_option("--fps", vi.fps, "Frames a second (default 30)")->check(CLI::Range(1, 240));
  viCmd->add_option("--from", vi.from, "Start, s of the recording or order (default its start)");
  viCmd->add_option("--to", vi.to, "End, s (default its end)");
  viCmd->add_option("--speed", vi.speed, "Seconds of recording a second of video (default 1)")->check(CLI::Range(0.01, 1000.0));
  // "follow PART" as one argument or two.
  viCmd->add_option("--camera", vi.camera, "auto (default), follow PART, or iso, front, back, left, right, top")->expected(1, 2);
  viCmd->add_flag("--order", vi.order, "Play the planned order of a scene, STEP or mesh file");
  viCmd->add_option("--step-seconds", vi.stepSeconds, "Seconds each step of the order takes (default 2)")->check(CLI::Range(0.05, 600.0));
  CLI::Option* viSweeps = viCmd->add_flag("--sweeps", vi.sweeps, "With --order: each way's swept volume drawn while its part comes home, and its nearest pass "
                                                                  "(a line between the nearest points, the part and distance in the caption)");
  viCmd->add_option("--voxel", vi.voxelMm, "With --sweeps: the swept volumes' voxel edge (mm, default 2)")->type_name("MM")->check(CLI::Range(0.1, 1e4))->needs(viSweeps);
  viCmd->callback([&] { command = [&] { return vaw::app::video(vi); }; });
#endif

  vaw::app::EvaluateArgs ev;
  CLI::App* evCmd = app.add_subcommand(
      "evaluate", "Which order puts an assembly together (a scene, a STEP file or a mesh file): every part's ways home "
                  "moved through the assembly, the precedence between parts, an order, and the parts no order can "
                  "put in place with what blocks them (docs/evaluation.md). One process per input: a folder goes "
                  "through GNU parallel or a Slurm job array.");
  evCmd->add_option("FILE", ev.file, "Scene, STEP or mesh file, or a bundled scene by its name")->required();
  evCmd->add_flag("--json", ev.json, "Print JSON");
  evCmd->add_option("--session", ev.sessions, "Recorded sessions of this assembly (vaw-sim run, the window's File > Save Session): "
                                              "per part what each assembler did, side by side")
      ->type_name("SESSION")->expected(1, -1);
  evCmd->add_option("--report", ev.report, "Write DIR/report.html with parts.csv, sequence.csv, sessions.csv and evaluation.json")
      ->type_name("DIR");
  evCmd->add_option("--up", ev.up, "CAD files: which way the assembly stands: auto (the default), the file's axis that points up or "
                                   "its direction as three numbers")
      ->check(upChoice);
  CLI::Option* ways = evCmd->add_flag("--ways,--sweeps", ev.ways, "Each way home walked past the parts already in: its least clearance to each, near misses "
                                        "flagged, and the space it needs swept (in the text, the JSON and the report with a picture of each)");
  evCmd->add_option("--threshold", ev.thresholdMm, "With --ways: closer than this to a part already in is a near miss (mm, default 5)")
      ->type_name("MM")->check(CLI::NonNegativeNumber)->needs(ways);
  evCmd->add_option("--voxel", ev.voxelMm, "With --ways: the swept volumes' voxel edge (mm, default 1; 0 leaves them out)")
      ->type_name("MM")->check(CLI::NonNegativeNumber)->needs(ways);
  addReaderLimits(evCmd, ev.import);
  evCmd->callback([&] { command = [&] { return vaw::app::evaluate(ev); }; });

  vaw::app::WorkPrecisionArgs wp;
  bool noPeers = false;
  CLI::App* wpCmd = app.add_subcommand(
      "work-precision", "Run every scenario (slide with stop, gear pendulum undamped and damped, tumbling block, "
                        "tennis racket) with every method at 30..1000 Hz, and the Bullet/ODE peers when built; write "
                        "DIR/work-precision.csv and one chart per scenario (PNG and SVG).");
  wpCmd->add_option("--out", wp.out, "Output directory")->type_name("DIR")->required();
  wpCmd->add_option("--repeats", wp.repeats, "Timed runs per point; the median is kept (default 5)")->check(wholeNumber(1, 1000));
  wpCmd->add_flag("--no-peers", noPeers, "Leave out the Bullet and ODE peers");
  wpCmd->callback([&] {
    wp.peers = !noPeers;
    command = [&] { return vaw::app::workPrecision(wp, argc, argv); };
  });

  CLI::App* trialsCmd = app.add_subcommand("trials", "Gravity-scale trials (docs/trials.md).");
  trialsCmd->require_subcommand(1);
  vaw::app::TrialsSimulateArgs sim;
  CLI::App* simCmd = trialsCmd->add_subcommand(
      "simulate", "Run the design against a simulated participant; with --out, through the crash-safe results file a "
                  "real session uses (an existing file is resumed); with --runs N, N participants (seeds MODEL.seed .. "
                  "+N-1, design seeds likewise) and how often the interval holds the model's PSE, for planning how many "
                  "trials a study needs.");
  simCmd->add_option("DESIGN", sim.design, "Trial design (.vaw-trial.json)")->required();
  simCmd->add_option("--participant", sim.participant, "Simulated participant (.vaw-participant.json)")->type_name("MODEL")->required();
  CLI::Option* outOpt = simCmd->add_option("--out", sim.out, "Results file to write or resume")->type_name("RESULTS");
  simCmd->add_option("--runs", sim.runs, "Simulated participants (default 1)")->check(wholeNumber(1, 100000))->excludes(outOpt);
  simCmd->add_flag("--json", sim.json, "Print JSON");
  simCmd->callback([&] { command = [&] { return vaw::app::trialsSimulate(sim); }; });

  vaw::app::TrialsAnalyzeArgs an;
  CLI::App* anCmd = trialsCmd->add_subcommand(
      "analyze", "Per participant and pooled: the PSE (or mean setting) with its 95 % interval, the objective "
                 "measures, and the head-demand model's scale.");
  anCmd->add_option("RESULTS", an.files, "Results files (.vaw-results.jsonl)")->required();
  anCmd->add_option("--png", an.png, "Draw answers against scale with the fitted curve")->type_name("FILE");
  anCmd->add_option("--lapse", an.lapse, "The fit's fixed lapse rate (default 0.02)")->check(numberIn(0.0, 0.5, true, "a rate in [0, 0.5)"));
  anCmd->add_flag("--json", an.json, "Print JSON");
  anCmd->callback([&] { command = [&] { return vaw::app::trialsAnalyze(an, argc, argv); }; });

  vaw::app::TrialsDemandArgs dm;
  CLI::App* dmCmd = trialsCmd->add_subcommand(
      "demand", "The head rotation needed to follow a part falling from eye level, and the largest gravity scale "
                "within the limits (docs/head-demand.md).");
  const auto positive = numberIn(1e-9, 1e9, false, "a positive number");
  dmCmd->add_option("--distance", dm.distance, "Viewing distance, m")->type_name("M")->required()->check(positive);
  dmCmd->add_option("--height", dm.height, "Fall height, m")->type_name("M")->required()->check(positive);
  dmCmd->add_option("--pitch-limit", dm.pitchLimit, "Head pitch rate limit, deg/s")->type_name("DEG_S")->check(positive);
  dmCmd->add_option("--yaw-limit", dm.yawLimit, "Head yaw rate limit, deg/s")->type_name("DEG_S")->check(positive);
  dmCmd->add_option("--acceleration-limit", dm.accelerationLimit, "Head acceleration limit, deg/s^2")->type_name("DEG_S2")->check(positive);
  dmCmd->add_flag("--yaw", dm.yaw, "Follow by turning the head sideways instead of down");
  dmCmd->callback([&] { command = [&] { return vaw::app::trialsDemand(dm); }; });

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // Name the (sub)command whose arguments were wrong, and keep exit status 2 for every usage error.
    std::string where = "vaw-sim";
    for (const CLI::App* sub = &app; sub != nullptr;) {
      const auto chosen = sub->get_subcommands();
      sub = chosen.empty() ? nullptr : chosen.front();
      if (sub) where += " " + sub->get_name();
    }
    std::string problem = e.what();
    if (where == "vaw-sim" && argc > 1 && argv[1][0] != '-')
      problem = std::string("unknown command \"") + argv[1] + "\" (the commands: inspect, states, run, clearance, sweep, evaluate, export, video, work-precision, trials)";
    std::fprintf(stderr, "%s: %s\nRun %s --help for the usage.\n", where.c_str(), problem.c_str(), where.c_str());
    return 2;
  }
  return command();
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
