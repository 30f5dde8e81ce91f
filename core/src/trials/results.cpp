#include "vaw/trials/results.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "../base/json_node.hpp"
#include "design_json.hpp"
#include "results_lines.hpp"

namespace vaw::trials {

using vaw::detail::Json;
using vaw::detail::Node;

namespace detail {

namespace {

Json parseLine(const std::string& text, const std::string& file, int line) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    std::string what = e.what();
    if (auto p = what.find("syntax error"); p != std::string::npos) what = what.substr(p);
    vaw::fail(file, "line " + std::to_string(line), "a whole JSON record", what);
  }
}

Judgement judgementFrom(const Node& n) {
  const std::string s = n.string();
  for (Judgement j : {Judgement::TooFast, Judgement::TooSlow, Judgement::First, Judgement::Second})
    if (s == name(j)) return j;
  n.fail("\"too-fast\", \"too-slow\", \"first\" or \"second\"");
}

bool sameScale(double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); }

// One record: its fields, and that it is the trial the design asks for at this point.
void readRecord(const Node& n, Procedure& procedure) {
  n.requireObject();
  const Trial& expected = *procedure.next();
  const bool setting = procedure.design().question.answers == AnswerKind::Setting;
  const bool twoInterval = expected.referenceScale.has_value();
  if (setting) n.allowOnly({"trial", "start_scale", "setting", "caught", "regrasp_time_s"});
  else if (twoInterval) n.allowOnly({"trial", "scale", "staircase", "reference_scale", "reference_first", "answer", "caught", "regrasp_time_s"});
  else n.allowOnly({"trial", "scale", "staircase", "answer", "caught", "regrasp_time_s"});

  const Node trial = n.get("trial");
  if (trial.integer() != expected.index)
    trial.fail("trial " + std::to_string(expected.index) + " (records are numbered from 0, one per answered trial, in order)");
  const Node scale = n.get(setting ? "start_scale" : "scale");
  if (!sameScale(scale.positive(), expected.scale))
    scale.fail(vaw::detail::describe(expected.scale) + ", the scale the design gives trial " + std::to_string(expected.index));
  if (expected.staircase) {
    const Node s = n.get("staircase");
    if (s.integer() != *expected.staircase) s.fail("staircase " + std::to_string(*expected.staircase) + ", the one the design asks at this trial");
  } else if (n.has("staircase")) {
    n.get("staircase").fail("no staircase (the design's method has none)");
  }
  if (twoInterval) {
    const Node r = n.get("reference_scale");
    if (!sameScale(r.positive(), *expected.referenceScale)) r.fail("the design's reference scale " + vaw::detail::describe(*expected.referenceScale));
    const Node first = n.get("reference_first");
    if (!first.json().is_boolean() || first.json().get<bool>() != expected.referenceFirst)
      first.fail(std::string(expected.referenceFirst ? "true" : "false") + ", the order the design's seed gives this trial");
  }

  Answer a;
  if (setting) a.response = Setting{n.get("setting").positive()};
  else a.response = judgementFrom(n.get("answer"));
  const Node caught = n.get("caught");
  if (!caught.json().is_boolean()) caught.fail("true or false");
  a.measures.caught = caught.json().get<bool>();
  const Node regrasp = n.get("regrasp_time_s");
  if (!regrasp.json().is_null()) a.measures.regraspTime_s = regrasp.nonNegative();
  try {
    procedure.answer(a);
  } catch (const std::invalid_argument& e) {
    n.get(setting ? "setting" : "answer").failWith("an answer that fits the trial", e.what());
  }
}

}  // namespace

std::string headerLine(const Design& d) {
  return Json{{"format", "vaw-trial-results"}, {"version", kResultsFormatVersion}, {"design", detail_json::designToJson(d)}}.dump() + "\n";
}

std::string recordLine(const Record& r) {
  Json j{{"trial", r.trial.index}};
  if (const auto* s = std::get_if<Setting>(&r.answer.response)) {
    j["start_scale"] = r.trial.scale;
    j["setting"] = s->scale;
  } else {
    j["scale"] = r.trial.scale;
    if (r.trial.staircase) j["staircase"] = *r.trial.staircase;
    if (r.trial.referenceScale) {
      j["reference_scale"] = *r.trial.referenceScale;
      j["reference_first"] = r.trial.referenceFirst;
    }
    j["answer"] = name(std::get<Judgement>(r.answer.response));
  }
  j["caught"] = r.answer.measures.caught;
  j["regrasp_time_s"] = r.answer.measures.regraspTime_s ? Json(*r.answer.measures.regraspTime_s) : Json(nullptr);
  return j.dump() + "\n";
}

Parsed parseResults(const std::string& text, const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::size_t wholeEnd = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
  if (wholeEnd == 0)
    vaw::fail(file, "line 1", "a header line ending in a newline",
              text.empty() ? "an empty file" : "a line cut off after " + std::to_string(text.size()) + " bytes");

  std::size_t begin = text.find('\n') + 1;
  const Json header = parseLine(text.substr(0, begin - 1), file, 1);
  const Node h(header, "line 1", file);
  h.requireObject();
  const Node format = h.get("format");
  if (format.string() != "vaw-trial-results") format.fail("\"vaw-trial-results\"");
  const Node version = h.get("version");
  if (version.integer() != kResultsFormatVersion) version.fail("version " + std::to_string(kResultsFormatVersion) + " (the version this vaw reads)");
  h.allowOnly({"format", "version", "design"});
  const Design design = detail_json::designFromNode(h.get("design"));
  Parsed out{ResultsFile{path, design, {}, std::nullopt}, Procedure(design)};

  int line = 2;
  for (; begin < wholeEnd; ++line) {
    const std::size_t end = text.find('\n', begin);
    const std::string lineText = text.substr(begin, end - begin);
    begin = end + 1;
    if (!out.procedure.next())
      vaw::fail(file, "line " + std::to_string(line), "no more records (the design's " + std::to_string(out.procedure.records().size()) + " trials are all answered)", vaw::detail::describe(lineText));
    const Json j = parseLine(lineText, file, line);
    readRecord(Node(j, "line " + std::to_string(line), file), out.procedure);
  }
  if (wholeEnd < text.size()) out.file.torn = TornTail{line, wholeEnd, text.size() - wholeEnd};
  out.file.records = out.procedure.records();
  return out;
}

}  // namespace detail

ResultsFile readResults(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) vaw::fail(file.string(), "", "an existing, readable results file", std::filesystem::exists(file) ? "unreadable" : "no such file");
  std::stringstream ss;
  ss << in.rdbuf();
  return detail::parseResults(ss.str(), file).file;
}

}  // namespace vaw::trials
