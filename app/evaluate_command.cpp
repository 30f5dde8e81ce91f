#include "evaluate_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "vaw/report/report.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/evaluation/session_stats.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw::app {

namespace {

using nlohmann::json;
using eval::travelText;

std::string blockers(const Assembly& a, const eval::Direction& d) {
  if (d.blockers.empty()) return "free";
  std::string s = "blocked by";
  for (std::size_t i = 0; i < d.blockers.size(); ++i) {
    char buf[160];
    const auto& b = d.blockers[i];
    // Within a twentieth of a millimetre: the two touch at home (the search locates a block to 0.01 mm).
    if (b.undecided)
      std::snprintf(buf, sizeof buf, "%s %s undecided past %.1f mm (the sweep's limit)", i ? "," : "", a.parts[b.by].name.c_str(), 1e3 * b.distance);
    else if (b.distance < 5e-5) std::snprintf(buf, sizeof buf, "%s %s at once", i ? "," : "", a.parts[b.by].name.c_str());
    else std::snprintf(buf, sizeof buf, "%s %s after %.1f mm", i ? "," : "", a.parts[b.by].name.c_str(), 1e3 * b.distance);
    s += buf;
  }
  return s;
}

json toJson(const Assembly& a, const eval::SequencePlan& plan, double seconds) {
  json j;
  j["assembly"] = a.name;
  j["base"] = a.parts[*plan.base].name;
  j["complete"] = plan.complete();
  json order = json::array();
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    json e{{"part", a.parts[p].name}, {"step", plan.step[i]}};
    if (const auto* way = plan.wayOf(p)) e["comes_home"] = {{"from", way->from}, {"direction", {-way->out.x(), -way->out.y(), -way->out.z()}}};
    if (const auto* sub = plan.subAssemblyOf(p)) e["sub_assembly"] = a.parts[sub->parts.front()].name;
    if (const auto* w = plan.wrapOf(p)) {
      json wrapped = json::array();
      for (const PartId r : w->wraps) wrapped.push_back(a.parts[r].name);
      e["wraps"] = wrapped;
    }
    json after = json::array();
    for (const auto& e2 : plan.precedence)
      if (e2.after == p)
        after.push_back({{"part", a.parts[e2.before].name}, {"reason", e2.reason == eval::Precedence::Reason::Partner ? "partner" : "blocks"}});
    e["after"] = after;
    order.push_back(e);
  }
  j["order"] = order;
  json checks = json::array();
  for (const auto& c : plan.checks) {
    json dirs = json::array();
    for (const auto& d : c.directions) {
      json bs = json::array();
      for (const auto& b : d.blockers) {
        json e{{"part", a.parts[b.by].name}, {"distance_m", b.distance}};
        if (b.undecided) e["undecided"] = true;
        bs.push_back(std::move(e));
      }
      dirs.push_back({{"from", d.from}, {"direction", {-d.out.x(), -d.out.y(), -d.out.z()}}, {"blockers", bs}});
    }
    checks.push_back({{"part", a.parts[c.part].name}, {"ways_home", dirs}});
  }
  j["parts"] = checks;
  json stuck = json::array();
  for (const auto& s : plan.stuck) {
    json e{{"part", a.parts[s.part].name}};
    json per = json::array();
    for (const auto& by : s.blockers) {
      json names = json::array();
      for (const PartId b : by) names.push_back(a.parts[b].name);
      per.push_back(names);
    }
    e["blocked_by"] = per;
    json waits = json::array();
    for (const PartId w : s.waitsFor) waits.push_back(a.parts[w].name);
    e["waits_for"] = waits;
    stuck.push_back(e);
  }
  j["no_order_inserts"] = stuck;
  json skipped = json::array();
  for (const PartId p : plan.skipped) skipped.push_back(a.parts[p].name);
  j["without_final_pose"] = skipped;
  j["pair_checks"] = plan.pairChecks;
  j["pair_checks_reused"] = plan.reused;
  j["undecided_checks"] = plan.undecided;
  j["checks"] = plan.evaluations;
  j["seconds"] = seconds;
  return j;
}

void printText(const Assembly& a, const eval::SequencePlan& plan, double seconds) {
  const std::size_t placed = plan.order.size() - 1;
  const std::size_t parts = placed + plan.stuck.size();
  std::printf("%s: %zu part%s on the base %s; %s\n", a.name.c_str(), parts, parts == 1 ? "" : "s", a.parts[*plan.base].name.c_str(),
              plan.complete() ? "an order puts every one of them in place"
                              : (std::to_string(plan.stuck.size()) + " can be put in place by no order").c_str());
  std::printf("\n%-5s %-20s %-40s %s\n", "step", "part", "comes home", "after");
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    std::string home = "(the base)", after;
    if (const auto* way = plan.wayOf(p)) home = travelText(way->out) + ": " + way->from;
    if (const auto* w = plan.wrapOf(p)) {
      std::string names;
      for (std::size_t k = 0; k < w->wraps.size(); ++k)
        names += (k == 0 ? "" : k + 1 == w->wraps.size() ? " and " : ", ") + a.parts[w->wraps[k]].name;
      home = "wraps " + names + ": flexible, fitted by hand after them";
    }
    if (const auto* sub = plan.subAssemblyOf(p)) {
      // A sub-assembly's parts are put together on the bench, then come home with its first.
      if (p == sub->parts.front()) home += ", carrying " + std::to_string(sub->parts.size() - 1) + " parts as one sub-assembly";
      else home = "put on " + a.parts[sub->parts.front()].name + " beforehand";
    }
    for (const auto& e : plan.precedence)
      if (e.after == p)
        after += (after.empty() ? "" : ", ") + a.parts[e.before].name + (e.reason == eval::Precedence::Reason::Partner ? " (partner)" : " (whose way it blocks)");
    std::printf("%-5d %-20s %-40s %s\n", plan.step[i], a.parts[p].name.c_str(), home.c_str(), after.c_str());
  }
  if (!plan.complete()) {
    std::printf("\nno order puts these in place:\n");
    for (const auto& s : plan.stuck) {
      std::printf("  %s:", a.parts[s.part].name.c_str());
      if (!s.waitsFor.empty()) {
        std::string names;
        for (const PartId w : s.waitsFor) names += (names.empty() ? "" : ", ") + a.parts[w].name;
        std::printf(" needs %s in place first, which no order puts there\n", names.c_str());
        continue;
      }
      const auto* c = plan.checkOf(s.part);
      for (std::size_t k = 0; k < c->directions.size(); ++k)
        std::printf("%s %s (%s): %s", k ? ";" : "", travelText(c->directions[k].out).c_str(), c->directions[k].from.c_str(),
                    blockers(a, c->directions[k]).c_str());
      std::printf("\n");
    }
  }
  if (!plan.skipped.empty()) {
    std::string names;
    for (const PartId p : plan.skipped) names += (names.empty() ? "" : ", ") + a.parts[p].name;
    std::printf("\nwithout a final pose, not in the sequence: %s\n", names.c_str());
  }
  std::printf("\nways home: every part's, moved through the assembly (%d pair checks, %d more answered by one of the same "
              "parts placed alike, %d distance and blocked checks, %.2f s)\n",
              plan.pairChecks, plan.reused, plan.evaluations, seconds);
  if (plan.undecided > 0)
    std::printf("  %d check%s ran out of their limit undecided: counted as blocked\n", plan.undecided, plan.undecided == 1 ? "" : "s");
  for (const auto& c : plan.checks) {
    std::printf("  %s\n", a.parts[c.part].name.c_str());
    for (const auto& d : c.directions)
      std::printf("    %-10s %-36s %s\n", travelText(d.out).c_str(), d.from.c_str(), blockers(a, d).c_str());
  }
}

void printWays(const Assembly& a, const report::WaysHome& ways) {
  std::size_t misses = 0;
  for (const auto& w : ways.ways) misses += w.nearMiss(ways.options.threshold) ? 1 : 0;
  std::printf("\nways home past the parts already in (near miss: under %.3g mm from a part it neither slides on nor rests on): %zu of %zu\n",
              1e3 * ways.options.threshold, misses, ways.ways.size());
  std::printf("  %-20s %-20s %10s %10s %10s  %s\n", "part", "nearest", "least mm", "at mm out", "swept cm3", "");
  for (const auto& w : ways.ways) {
    const eval::WayObject* n = w.nearest();
    std::printf("  %-20s %-20s %10s %10s %10s  %s\n", a.parts[w.part].name.c_str(), n ? a.parts[n->part].name.c_str() : "-",
                n ? report::formatNumber(1e3 * n->least).c_str() : "", n ? report::formatNumber(1e3 * n->at).c_str() : "",
                w.swept ? report::formatNumber(1e6 * w.swept->volume).c_str() : "", w.nearMiss(ways.options.threshold) ? "near miss" : "");
  }
}

}  // namespace

int evaluate(const EvaluateArgs& args) {
  ImporterRegistry importers;
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  const bool tty = isatty(STDERR_FILENO) != 0;
  int shown = -1;
  const ProgressFn progress = [tty, &shown](double fraction, const std::string& stage) {
    const int percent = static_cast<int>(fraction * 100.0);
    if (tty && percent != shown) {
      shown = percent;
      std::fprintf(stderr, "\rvaw-sim: %3d %% %-50.50s", percent, stage.c_str());
    }
    return true;
  };
  try {
    LoadOptions options;
    if (!args.up.empty()) options.cadUp = args.up;
    options.import = args.import;
    const Assembly a = loadAny(resolveScenePath(args.file), importers, options, progress);
    const auto start = std::chrono::steady_clock::now();
    const eval::SequencePlan plan = eval::planSequence(a, {}, progress);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Each session replayed on this assembly (its recorded scene hash must match).
    std::vector<eval::SessionStats> sessions;
    if (!args.sessions.empty()) {
      const auto scene = sim::Scene::build(a);
      for (const auto& file : args.sessions) {
        if (tty) std::fprintf(stderr, "\rvaw-sim: replaying %-50.50s", file.c_str());
        const sim::Session session = sim::loadSession(file);
        sim::checkScene(session, *scene);
        sessions.push_back(eval::sessionStats(scene, session, std::filesystem::path(file).stem().stem().string()));
      }
    }
    // Each way home walked past the parts already in, and swept.
    std::optional<report::WaysHome> ways;
    if (args.ways) {
      ways.emplace();
      ways->options.threshold = 1e-3 * args.thresholdMm;
      ways->options.voxel = 1e-3 * args.voxelMm;
      ways->ways = eval::wayClearances(a, plan, ways->options, progress);
    }
    if (tty) std::fprintf(stderr, "\r%70s\r", "");
    if (args.json) {
      json j = toJson(a, plan, seconds);
      if (ways) j["ways"] = report::waysJson(a, *ways);
      if (!sessions.empty()) {
        json rows = json::array();
        for (const auto& r : report::partRows(a, plan, sessions))
          rows.push_back({{"part", r.name}, {"placed_in", r.placedIn}, {"time_to_place_mean_s", r.timeToPlace.mean},
                          {"time_to_place_sd_s", r.timeToPlace.sd}, {"grabs_mean", r.grabs.mean}, {"drops_mean", r.drops.mean},
                          {"refusals_mean", r.refusals.mean}, {"carried_mean_m", r.carried.mean}, {"estimate_s", r.estimate.total_s()}});
        j["sessions"] = rows;
      }
      std::cout << j.dump(2) << '\n';
    } else {
      printText(a, plan, seconds);
      if (ways) printWays(a, *ways);
      if (!sessions.empty()) {
        std::printf("\n%zu session%s: per part, mean (sd) over the sessions, and the design-for-assembly estimate\n", sessions.size(),
                    sessions.size() == 1 ? "" : "s");
        std::printf("  %-20s %8s %16s %7s %7s %9s %10s %10s\n", "part", "placed", "time to place s", "grabs", "drops", "refusals",
                    "carried m", "estimate s");
        for (const auto& r : report::partRows(a, plan, sessions)) {
          if (r.step == "base") continue;
          char time[48] = "";
          if (r.timeToPlace.n > 0) std::snprintf(time, sizeof time, "%.2f (%.2f)", r.timeToPlace.mean, r.timeToPlace.sd);
          std::printf("  %-20s %5d/%-2d %16s %7.1f %7.1f %9.1f %10.3f %10.2f\n", r.name.c_str(), r.placedIn, r.sessions, time, r.grabs.mean,
                      r.drops.mean, r.refusals.mean, r.carried.mean, r.estimate.total_s());
        }
      }
    }
    if (!args.report.empty()) {
      std::fflush(stdout);  // the table before the note, when both go to one file
      // A CAD assembly's parts come with their assembled places: what overlaps there is in the report too.
      std::optional<std::vector<collision::Interference>> overlaps;
      if (!a.cadFile.empty()) overlaps = collision::interferences(a, collision::assembledPoses(a));
      const report::ReportFiles files =
          report::writeReport(a, plan, sessions, args.report, {}, ways ? &*ways : nullptr, overlaps ? &*overlaps : nullptr);
      std::fprintf(stderr, "vaw-sim: wrote %s (and parts.csv, sequence.csv, sessions.csv%s, evaluation.json beside it)\n",
                   files.html.string().c_str(), ways ? ", ways.csv" : "");
    }
    // Scripts and CI tell "no order" from success without reading the table (docs/evaluation.md).
    return plan.complete() ? 0 : kExitNoOrder;
  } catch (const InputError& e) {
    if (tty) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace vaw::app
