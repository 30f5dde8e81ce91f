// `vaw-sim trials`: run a design against a simulated participant, analyse results files, and print
// the head-demand model's numbers (docs/trials.md, docs/head-demand.md).
#include "trials_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <system_error>

#include "vaw/error.hpp"
#include "vaw/human/head_demand.hpp"
#include "vaw/trials/analysis.hpp"
#include "vaw/trials/runner.hpp"
#include "vaw/trials/simulated_participant.hpp"
#ifdef VAW_HAVE_CHARTS
#include "vaw/ui/trials_chart.hpp"
#endif

namespace vaw::app {

namespace {

using nlohmann::json;
using namespace vaw::trials;

json interval(const Interval& i) {
  return {i.lo > 0 ? json(i.lo) : json(nullptr), std::isfinite(i.hi) ? json(i.hi) : json(nullptr)};
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string text(const Interval& i) {
  return "[" + (i.lo > 0 ? fmt(i.lo) : std::string("unbounded")) + ", " + (std::isfinite(i.hi) ? fmt(i.hi) : std::string("unbounded")) + "]";
}

json toJson(const human::ScaleRecommendation& r) {
  const auto& d = r.atFullGravity;
  return {{"recommended_scale", r.recommendedScale},
          {"max_scale", r.maxScale},
          {"limited_by", r.limitedBy},
          {"rate_limit_deg_s", r.rateLimit_deg_s},
          {"at_full_gravity",
           {{"fall_time_s", d.fallTime_s},
            {"final_angle_deg", d.finalAngle_deg},
            {"peak_rate_deg_s", d.peakRate_deg_s},
            {"peak_rate_time_s", d.peakRateTime_s},
            {"peak_acceleration_deg_s2", d.peakAcceleration_deg_s2},
            {"peak_acceleration_time_s", d.peakAccelerationTime_s}}}};
}

json toJson(const ConditionAnalysis& a) {
  const auto& c = a.condition;
  json out{{"scenario", name(c.scenario)}, {"motion", name(c.motion)}, {"answers", name(c.answers)}};
  if (c.referenceScale) out["reference_scale"] = *c.referenceScale;
  if (c.viewing) out["viewing"] = {{"distance_m", c.viewing->geometry.distance_m}, {"fall_height_m", c.viewing->geometry.fallHeight_m}};
  json participants = json::array();
  for (const auto& p : a.participants) {
    json j{{"participant", p.participant}, {"files", p.files}, {"methods", p.methods}, {"trials", p.trials}, {"caught", p.caught},
           {"median_regrasp_s", p.medianRegrasp_s ? json(*p.medianRegrasp_s) : json(nullptr)}};
    if (p.fit) {
      const auto& f = *p.fit;
      j["fit"] = {{"ok", f.ok}, {"problem", f.problem}, {"pse", f.ok ? json(f.pse) : json(nullptr)},
                  {"interval", f.ok ? interval(f.pseInterval) : json(nullptr)}, {"sigma_log", f.sigmaLog},
                  {"lapse", f.lapse}, {"log_likelihood", f.logLikelihood}};
    }
    if (p.settings) {
      const auto& s = *p.settings;
      j["settings"] = {{"ok", s.ok}, {"problem", s.problem}, {"n", s.settings}, {"geometric_mean", s.geometricMean},
                       {"interval", interval(s.meanInterval)}, {"sd_log", s.sdLog}, {"median", s.median},
                       {"median_interval", interval(s.medianInterval)}, {"median_interval_coverage", s.medianCoverage}};
    }
    if (!p.reversalMeans.empty()) j["staircase_reversal_means"] = p.reversalMeans;
    json scales = json::array();
    for (const auto& s : p.perScale)
      scales.push_back({{"scale", s.scale}, {"trials", s.trials}, {"faster", s.faster}, {"caught", s.caught},
                        {"median_regrasp_s", s.medianRegrasp_s ? json(*s.medianRegrasp_s) : json(nullptr)}});
    j["per_scale"] = scales;
    participants.push_back(j);
  }
  out["participants"] = participants;
  if (a.pooled) out["pooled"] = {{"participants", a.pooled->participants}, {"estimate", a.pooled->estimate}, {"interval", interval(a.pooled->interval)}};
  if (a.predicted) out["head_demand_model"] = toJson(*a.predicted);
  out["notes"] = a.notes;
  return out;
}

void print(const ConditionAnalysis& a) {
  const auto& c = a.condition;
  std::printf("%s, %s scale, answers %s", std::string(name(c.scenario)).c_str(), std::string(name(c.motion)).c_str(),
              std::string(name(c.answers)).c_str());
  if (c.referenceScale) std::printf(" (reference %.3g)", *c.referenceScale);
  std::printf(":\n");
  const bool settings = c.answers == AnswerKind::Setting;
  std::printf("  %-12s %-30s %7s %10s %-22s %8s %8s %s\n", "participant", "method", "trials", settings ? "mean set" : "PSE",
              "95 % interval", "caught", "regrasp", settings ? "median [interval, coverage]" : "spread (ln)");
  for (const auto& p : a.participants) {
    std::string methods;
    for (const auto& m : p.methods) methods += (methods.empty() ? "" : "+") + m;
    const auto est = p.estimate();
    char extra[128] = "";
    if (p.settings && p.settings->ok)
      std::snprintf(extra, sizeof extra, "%.4f %s %.0f %%", p.settings->median, text(p.settings->medianInterval).c_str(),
                    100.0 * p.settings->medianCoverage);
    else if (p.fit && p.fit->ok)
      std::snprintf(extra, sizeof extra, "%.3f", p.fit->sigmaLog);
    char regrasp[32] = "-";
    if (p.medianRegrasp_s) std::snprintf(regrasp, sizeof regrasp, "%.2f s", *p.medianRegrasp_s);
    std::printf("  %-12s %-30s %7d %10s %-22s %3d/%-4d %8s %s\n", p.participant.c_str(), methods.c_str(), p.trials,
                est ? fmt(*est).c_str() : "none", est ? text(p.interval()).c_str() : "-", p.caught,
                p.trials, regrasp, extra);
    if (!p.reversalMeans.empty()) {
      std::printf("  %-12s staircase reversal means:", "");
      for (double r : p.reversalMeans) std::printf(" %.4f", r);
      std::printf("\n");
    }
  }
  if (a.pooled)
    std::printf("  pooled (%d participant%s): %.4f %s\n", a.pooled->participants, a.pooled->participants == 1 ? "" : "s",
                a.pooled->estimate, text(a.pooled->interval).c_str());
  if (a.predicted)
    std::printf("  head-demand model: %.4f (peak %.1f deg/s at 1 g against the %s limit %.0f deg/s; largest scale within it %.3f)\n",
                a.predicted->recommendedScale, a.predicted->atFullGravity.peakRate_deg_s, a.predicted->limitedBy.c_str(),
                a.predicted->rateLimit_deg_s, a.predicted->maxScale);
  for (const auto& n : a.notes) std::printf("  note: %s\n", n.c_str());
}

}  // namespace

int trialsSimulate(const TrialsSimulateArgs& args) {
  const std::string& designFile = args.design;
  const std::string& modelFile = args.participant;
  const std::string& out = args.out;
  const int runs = args.runs;
  const bool asJson = args.json;
  const Design design = loadDesign(designFile);
  const ParticipantModel model = loadParticipantModel(modelFile);

  if (runs == 1) {
    ResultsFile results{out.empty() ? designFile : out, design, {}, std::nullopt};
    if (!out.empty()) {
      Runner r = Runner::open(design, out);
      if (r.recovered()) std::fprintf(stderr, "vaw-sim: %s: cut off a torn record at line %d (%ju bytes); asking that trial again\n", out.c_str(), r.recovered()->line, r.recovered()->bytes);
      if (r.answered() > 0) std::fprintf(stderr, "vaw-sim: %s: resuming after %d answered trials\n", out.c_str(), r.answered());
      while (r.next()) r.answer(simulateAnswer(model, *r.next()));
      results.records = r.records();
    } else {
      Procedure p(design);
      while (p.next()) p.answer(simulateAnswer(model, *p.next()));
      results.records = p.records();
    }
    const auto analysis = analyze({results});
    if (asJson) {
      json j = toJson(analysis.front());
      j["true_pse"] = model.pse;
      std::cout << j.dump(2) << '\n';
    } else {
      print(analysis.front());
      std::printf("  simulated participant's PSE: %.4f\n", model.pse);
      if (!out.empty()) std::printf("wrote %s (%zu trials)\n", out.c_str(), results.records.size());
    }
    return 0;
  }

  int covered = 0, estimated = 0;
  std::vector<double> widths, trialCounts, errors;
  for (int i = 0; i < runs; ++i) {
    Design d = design;
    d.seed += static_cast<std::uint64_t>(i);
    ParticipantModel m = model;
    m.seed += static_cast<std::uint64_t>(i);
    Procedure p(d);
    while (p.next()) p.answer(simulateAnswer(m, *p.next()));
    const auto a = analyze({ResultsFile{designFile, d, p.records(), std::nullopt}});
    const ParticipantResult& r = a.front().participants.front();
    trialCounts.push_back(static_cast<double>(r.trials));
    if (const auto e = r.estimate()) {
      ++estimated;
      covered += r.interval().contains(model.pse) ? 1 : 0;
      widths.push_back(r.interval().hi / r.interval().lo);
      errors.push_back(std::abs(std::log(*e / model.pse)));
    }
  }
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const double coverage = estimated ? static_cast<double>(covered) / estimated : 0.0;
  if (asJson) {
    std::cout << json{{"runs", runs}, {"estimated", estimated}, {"covered", covered}, {"coverage", coverage},
                      {"true_pse", model.pse}, {"median_trials", median(trialCounts)},
                      {"median_interval_ratio", median(widths)}, {"median_abs_log_error", median(errors)}}
                     .dump(2)
              << '\n';
  } else {
    std::printf("%d simulated participants (PSE %.4f, spread %.3f ln, lapse %.3f) through %s, %s:\n", runs, model.pse,
                model.sigmaLog, model.lapse, std::string(methodName(design.method)).c_str(), design.name.c_str());
    std::printf("  median trials %.0f; estimates %d; intervals holding the true PSE %d (%.1f %%)\n", median(trialCounts),
                estimated, covered, 100.0 * coverage);
    std::printf("  median interval hi/lo %.3f; median |error| %.1f %%\n", median(widths), 100.0 * (std::exp(median(errors)) - 1.0));
  }
  return 0;
}

int trialsAnalyze(const TrialsAnalyzeArgs& args, int argc, char** argv) {
  const std::vector<std::string>& files = args.files;
  const std::string& png = args.png;
  const bool asJson = args.json;
  AnalysisOptions options;
  if (args.lapse) options.lapse = *args.lapse;
  std::vector<ResultsFile> results;
  for (const auto& f : files) {
    results.push_back(readResults(f));
    if (const auto& t = results.back().torn)
      std::fprintf(stderr, "vaw-sim: warning: %s: line %d is a record cut off mid-write (%ju bytes); left out (resuming the session cuts it off and asks that trial again)\n",
                   f.c_str(), t->line, t->bytes);
  }
  const auto analyses = analyze(results, options);
  if (asJson) {
    json all = json::array();
    for (const auto& a : analyses) all.push_back(toJson(a));
    std::cout << json{{"lapse", options.lapse}, {"confidence", options.confidence}, {"conditions", all}}.dump(2) << '\n';
  } else {
    for (const auto& a : analyses) print(a);
  }
  if (!png.empty()) {
#ifdef VAW_HAVE_CHARTS
    for (const auto& f : ui::writeTrialsCharts(analyses, png, argc, argv)) std::fprintf(asJson ? stderr : stdout, "wrote %s\n", f.c_str());
#else
    (void)argc;
    (void)argv;
    std::fprintf(stderr, "vaw-sim: built without Qt Charts; no chart written\n");
#endif
  }
  return 0;
}

int trialsDemand(const TrialsDemandArgs& args) {
  const human::ViewingGeometry g{args.distance, args.height};
  human::HeadLimits limits;
  if (args.pitchLimit) limits.pitchRate_deg_s = *args.pitchLimit;
  if (args.yawLimit) limits.yawRate_deg_s = *args.yawLimit;
  if (args.accelerationLimit) limits.acceleration_deg_s2 = *args.accelerationLimit;
  const auto axis = args.yaw ? human::FollowAxis::Yaw : human::FollowAxis::Pitch;
  const auto r = human::recommendScale(g, limits, axis);
  const auto& d = r.atFullGravity;
  std::printf("a part dropped at eye level %.3g m away, falling %.3g m at 1 g (%.5g m/s^2):\n", g.distance_m, g.fallHeight_m, kStandardGravity);
  std::printf("  fall time %.4f s, ends %.2f deg below the horizon\n", d.fallTime_s, d.finalAngle_deg);
  std::printf("  peak head rate %.2f deg/s at %.4f s%s\n", d.peakRate_deg_s, d.peakRateTime_s,
              d.peakRateTime_s < d.fallTime_s ? "" : " (at landing)");
  std::printf("  peak head acceleration %.1f deg/s^2 at release\n", d.peakAcceleration_deg_s2);
  std::printf("  largest scale within the %s limit: %.4f; recommended scale %.4f\n", r.limitedBy.c_str(), r.maxScale, r.recommendedScale);
  return 0;
}

}  // namespace vaw::app
