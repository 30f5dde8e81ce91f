#include "vaw/trials/design.hpp"

#include <array>
#include <cmath>
#include <utility>

#include "../base/json_node.hpp"
#include "design_json.hpp"

namespace vaw::trials {

using detail::Json;
using detail::Node;

namespace {

constexpr std::array<std::pair<Scenario, const char*>, 4> kScenarios{{{Scenario::DropFromHand, "drop-from-hand"},
                                                                      {Scenario::Throw, "throw"},
                                                                      {Scenario::SlideOffTiltedBase, "slide-off-tilted-base"},
                                                                      {Scenario::GearPendulum, "gear-pendulum"}}};
constexpr std::array<std::pair<MotionKind, const char*>, 3> kMotions{
    {{MotionKind::FreeFlight, "free-flight"}, {MotionKind::Slide, "slide"}, {MotionKind::Rotation, "rotation"}}};
constexpr std::array<std::pair<AnswerKind, const char*>, 3> kAnswers{{{AnswerKind::TooFastTooSlow, "too-fast-too-slow"},
                                                                      {AnswerKind::TwoInterval, "two-interval"},
                                                                      {AnswerKind::Setting, "setting"}}};

template <typename E, std::size_t N>
E pick(const Node& n, const std::array<std::pair<E, const char*>, N>& table) {
  const std::string s = n.string();
  for (const auto& [value, text] : table)
    if (s == text) return value;
  std::string list;
  for (const auto& [value, text] : table) list += (list.empty() ? "" : ", ") + std::string("\"") + text + "\"";
  n.fail("one of " + list);
}

template <typename E, std::size_t N>
const char* text(E v, const std::array<std::pair<E, const char*>, N>& table) {
  for (const auto& [value, t] : table)
    if (value == v) return t;
  return "?";
}

int positiveInteger(const Node& n) {
  const int v = n.integer();
  if (v < 1) n.fail("an integer >= 1");
  return v;
}

ScaleRange range(const Node& n) {
  if (!n.json().is_array() || n.size() != 2) n.fail("[min, max] scales");
  const ScaleRange r{n.at(0).positive(), n.at(1).positive()};
  if (!(r.min < r.max)) n.failWith("min < max", detail::describe(n.json()));
  return r;
}

double scaleIn(const Node& n, const ScaleRange& r) {
  const double v = n.positive();
  if (v < r.min || v > r.max)
    n.fail("a scale within the range [" + detail::describe(r.min) + ", " + detail::describe(r.max) + "]");
  return v;
}

Method parseMethod(const Node& m) {
  m.requireObject();
  const Node kind = m.get("kind");
  const std::string k = kind.string();
  if (k == "adjustment") {
    m.allowOnly({"kind", "trials", "range", "start_range"});
    Adjustment a;
    a.trials = positiveInteger(m.get("trials"));
    a.range = range(m.get("range"));
    a.start = range(m.get("start_range"));
    if (a.start.min < a.range.min || a.start.max > a.range.max)
      m.get("start_range").fail("a start range inside the range");
    return a;
  }
  if (k == "constant-stimuli") {
    m.allowOnly({"kind", "scales", "repetitions"});
    ConstantStimuli c;
    const Node scales = m.get("scales");
    scales.requireArray();
    if (scales.size() < 2) scales.fail("at least two scales");
    for (std::size_t i = 0; i < scales.size(); ++i) c.scales.push_back(scales.at(i).positive());
    c.repetitions = positiveInteger(m.get("repetitions"));
    return c;
  }
  if (k == "staircase") {
    m.allowOnly({"kind", "start_low", "start_high", "step_factors", "n_up", "n_down", "min_trials", "min_reversals",
                 "max_trials", "range"});
    Staircase s;
    s.range = range(m.get("range"));
    s.startLow = scaleIn(m.get("start_low"), s.range);
    s.startHigh = scaleIn(m.get("start_high"), s.range);
    if (!(s.startLow < s.startHigh)) m.get("start_high").fail("a scale above start_low");
    const Node steps = m.get("step_factors");
    steps.requireArray();
    if (steps.size() == 0) steps.fail("at least one step factor");
    s.stepFactors.clear();
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const double f = steps.at(i).number();
      if (!(f > 1.0)) steps.at(i).fail("a factor > 1 (the scale is multiplied or divided by it)");
      s.stepFactors.push_back(f);
    }
    s.nUp = positiveInteger(m.get("n_up"));
    s.nDown = positiveInteger(m.get("n_down"));
    s.minTrials = positiveInteger(m.get("min_trials"));
    s.minReversals = m.get("min_reversals").integer();
    if (s.minReversals < 0) m.get("min_reversals").fail("an integer >= 0");
    s.maxTrials = positiveInteger(m.get("max_trials"));
    if (s.maxTrials < s.minTrials) m.get("max_trials").fail("an integer >= min_trials");
    return s;
  }
  if (k == "quest") {
    m.allowOnly({"kind", "trials", "prior_scale", "prior_sd_log", "sigma_log", "lapse", "range"});
    Quest q;
    q.trials = positiveInteger(m.get("trials"));
    q.range = range(m.get("range"));
    q.priorScale = scaleIn(m.get("prior_scale"), q.range);
    q.priorSdLog = m.get("prior_sd_log").positive();
    q.sigmaLog = m.get("sigma_log").positive();
    q.lapse = m.get("lapse").nonNegative();
    if (q.lapse >= 0.5) m.get("lapse").fail("a lapse rate below 0.5");
    return q;
  }
  kind.fail("one of \"adjustment\", \"constant-stimuli\", \"staircase\", \"quest\"");
}

Json rangeJson(const ScaleRange& r) { return Json::array({r.min, r.max}); }

Json methodJson(const Method& method) {
  return std::visit(
      [](const auto& m) -> Json {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, Adjustment>) {
          return {{"kind", "adjustment"}, {"trials", m.trials}, {"range", rangeJson(m.range)}, {"start_range", rangeJson(m.start)}};
        } else if constexpr (std::is_same_v<T, ConstantStimuli>) {
          return {{"kind", "constant-stimuli"}, {"scales", m.scales}, {"repetitions", m.repetitions}};
        } else if constexpr (std::is_same_v<T, Staircase>) {
          return {{"kind", "staircase"},       {"start_low", m.startLow},         {"start_high", m.startHigh},
                  {"step_factors", m.stepFactors}, {"n_up", m.nUp},               {"n_down", m.nDown},
                  {"min_trials", m.minTrials}, {"min_reversals", m.minReversals}, {"max_trials", m.maxTrials},
                  {"range", rangeJson(m.range)}};
        } else {
          return {{"kind", "quest"},        {"trials", m.trials},     {"prior_scale", m.priorScale},
                  {"prior_sd_log", m.priorSdLog}, {"sigma_log", m.sigmaLog}, {"lapse", m.lapse},
                  {"range", rangeJson(m.range)}};
        }
      },
      method);
}

// Which motion kinds a scenario shows: a drop or a throw is free flight; a part sliding off the base
// slides, then flies; the gear turns on its shaft.
bool shows(Scenario s, MotionKind m) {
  switch (s) {
    case Scenario::DropFromHand:
    case Scenario::Throw: return m == MotionKind::FreeFlight;
    case Scenario::SlideOffTiltedBase: return m == MotionKind::Slide || m == MotionKind::FreeFlight;
    case Scenario::GearPendulum: return m == MotionKind::Rotation;
  }
  return false;
}

}  // namespace

std::string_view name(Scenario s) { return text(s, kScenarios); }
std::string_view name(MotionKind m) { return text(m, kMotions); }
std::string_view name(AnswerKind a) { return text(a, kAnswers); }

std::string_view methodName(const Method& m) {
  static constexpr std::array<const char*, 4> names{"adjustment", "constant-stimuli", "staircase", "quest"};
  return names[m.index()];
}

namespace detail_json {

Design designFromNode(const Node& root) {
  root.requireObject();
  // The format is checked before anything else, so that a file of another kind says what it is
  // rather than failing on its first unexpected key.
  const Node format = root.get("format");
  if (format.string() != "vaw-trial-design") format.fail("\"vaw-trial-design\"");
  const Node version = root.get("version");
  if (version.integer() != kDesignFormatVersion)
    version.fail("version " + std::to_string(kDesignFormatVersion) + " (the version this vaw reads)");
  root.allowOnly({"format", "version", "name", "participant", "seed", "scenario", "motion", "blind", "question", "method",
                  "viewing"});
  Design d;
  d.name = root.get("name").string();
  d.participant = root.get("participant").string();
  if (d.participant.empty()) root.get("participant").fail("a non-empty participant id");
  const Node seed = root.get("seed");
  if (!seed.json().is_number_unsigned()) seed.fail("a non-negative integer (every random choice derives from it)");
  d.seed = seed.json().get<std::uint64_t>();
  d.scenario = pick(root.get("scenario"), kScenarios);
  d.motion = pick(root.get("motion"), kMotions);
  if (!shows(d.scenario, d.motion))
    root.get("motion").fail("a motion kind that the scenario \"" + std::string(name(d.scenario)) + "\" shows");
  if (const auto blind = root.opt("blind")) {
    if (!blind->json().is_boolean()) blind->fail("true or false");
    d.blind = blind->json().get<bool>();
  }
  const Node q = root.get("question");
  q.allowOnly({"text", "answers", "reference_scale"});
  d.question.text = q.get("text").string();
  d.question.answers = pick(q.get("answers"), kAnswers);
  if (d.question.answers == AnswerKind::TwoInterval) d.question.referenceScale = q.get("reference_scale").positive();
  else if (q.has("reference_scale")) q.get("reference_scale").fail("no reference scale (only two-interval answers have one)");
  d.method = parseMethod(root.get("method"));
  const bool adjustment = std::holds_alternative<Adjustment>(d.method);
  if (adjustment != (d.question.answers == AnswerKind::Setting))
    q.get("answers").fail(adjustment ? "\"setting\" (the method of adjustment asks for a setting)"
                                     : "\"too-fast-too-slow\" or \"two-interval\" (only adjustment asks for a setting)");
  if (const auto v = root.opt("viewing")) {
    // The demand model is about following a falling part; rotation and sliding stay where they are.
    if (d.motion != MotionKind::FreeFlight) v->fail("no viewing block (the head-demand model covers free flight only)");
    v->allowOnly({"distance_m", "fall_height_m", "pitch_limit_deg_s", "yaw_limit_deg_s", "acceleration_limit_deg_s2"});
    Viewing viewing;
    viewing.geometry.distance_m = v->get("distance_m").positive();
    viewing.geometry.fallHeight_m = v->get("fall_height_m").positive();
    if (const auto p = v->opt("pitch_limit_deg_s")) viewing.limits.pitchRate_deg_s = p->positive();
    if (const auto y = v->opt("yaw_limit_deg_s")) viewing.limits.yawRate_deg_s = y->positive();
    if (const auto a = v->opt("acceleration_limit_deg_s2")) viewing.limits.acceleration_deg_s2 = a->positive();
    d.viewing = viewing;
  }
  return d;
}

Json designToJson(const Design& d) {
  Json q{{"text", d.question.text}, {"answers", text(d.question.answers, kAnswers)}};
  if (d.question.answers == AnswerKind::TwoInterval) q["reference_scale"] = d.question.referenceScale;
  Json j{{"format", "vaw-trial-design"},
         {"version", kDesignFormatVersion},
         {"name", d.name},
         {"participant", d.participant},
         {"seed", d.seed},
         {"scenario", text(d.scenario, kScenarios)},
         {"motion", text(d.motion, kMotions)},
         {"blind", d.blind},
         {"question", q},
         {"method", methodJson(d.method)}};
  if (d.viewing) {
    Json v{{"distance_m", d.viewing->geometry.distance_m},
           {"fall_height_m", d.viewing->geometry.fallHeight_m},
           {"pitch_limit_deg_s", d.viewing->limits.pitchRate_deg_s},
           {"yaw_limit_deg_s", d.viewing->limits.yawRate_deg_s}};
    if (d.viewing->limits.acceleration_deg_s2) v["acceleration_limit_deg_s2"] = *d.viewing->limits.acceleration_deg_s2;
    j["viewing"] = v;
  }
  return j;
}

}  // namespace detail_json

Design loadDesign(const std::filesystem::path& file) {
  const Json j = detail::readJsonFile(file);
  const std::string f = file.string();
  return detail_json::designFromNode(Node(j, "", f));
}

std::string toJson(const Design& d) { return detail_json::designToJson(d).dump(2); }

}  // namespace vaw::trials
