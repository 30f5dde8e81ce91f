#pragma once
// The evaluation report (docs/evaluation.md, "The report"): presentation of what the core's evaluation
// found, in a library of its own (docs/architecture.md) that `vaw-sim evaluate` and the window link. One self-contained HTML page (pictures of the
// assembly and of each step of the order, the tables, the chart of time per part, each session's timeline)
// that opens in a browser with nothing else installed, and the same numbers as CSV and JSON. Every file is
// written through vaw::AtomicFile and published together, so a failed write leaves the previous report.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vaw/collision/interference.hpp"
#include "vaw/evaluation/dfa.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/evaluation/session_stats.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/importer.hpp"

namespace vaw::report {

using eval::DfaEstimate;
using eval::SequencePlan;
using eval::SessionStats;
using eval::Spread;

// One part's line of the parts table, as the HTML, parts.csv and evaluation.json all give it.
struct PartRow {
  PartId part = 0;
  std::string name;
  std::string step;          // its step in the order, "no order" or "base"
  std::string comesHome;     // "down: insert on stud-1"
  std::string blockedBy;     // for parts no order inserts
  DfaEstimate estimate;
  // Over the sessions (empty when there are none): sessions it was placed in, time to place, attempts.
  int sessions = 0, placedIn = 0;
  Spread timeToPlace, grabs, drops, refusals, carried;
  std::string hands;         // what held it, over all sessions
};

std::vector<PartRow> partRows(const Assembly& assembly, const SequencePlan& plan, const std::vector<SessionStats>& sessions);

// "%.3f", or "" for a spread without values: how every number appears in the HTML and the CSV alike.
std::string formatNumber(double v);

struct ReportFiles {
  std::filesystem::path html, partsCsv, sequenceCsv, sessionsCsv, json;
  std::filesystem::path waysCsv;  // with the ways home's clearances only
  std::filesystem::path interferencesCsv;  // with what overlaps at rest only
};

// The ways home's clearance and space (eval::wayClearances), for the report's section on them: a table,
// ways.csv, evaluation.json's "ways", and a picture of each way (near misses first, a few dozen at most).
struct WaysHome {
  std::vector<eval::WayClearance> ways;
  eval::WayClearanceOptions options;  // what they were measured with
};

// The ways home as numbers (metres), as evaluation.json and `vaw-sim evaluate --json` give them: the
// options, and per way its part, direction out, length, what it slides on and rests on, whether it is a
// near miss, every part within reach along it and its swept volume.
nlohmann::json waysJson(const Assembly& assembly, const WaysHome& ways);

// Writes report.html, parts.csv, sequence.csv, sessions.csv and evaluation.json (and ways.csv) into `dir` (created when
// missing). Throws vaw::OutputError naming the file when one cannot be written. `progress` hears of each
// picture drawn; when it returns false the report is abandoned (vaw::LoadCancelled) before any file is
// written. `ways` (may be null) adds the ways home's section.
// `overlaps` (may be null) adds what overlaps at rest (collision::interferences): a table, clashes first,
// interferences.csv and evaluation.json's "interferences".
ReportFiles writeReport(const Assembly& assembly, const SequencePlan& plan, const std::vector<SessionStats>& sessions,
                        const std::filesystem::path& dir, const ProgressFn& progress = {}, const WaysHome* ways = nullptr,
                        const std::vector<collision::Interference>* overlaps = nullptr);

}  // namespace vaw::report
