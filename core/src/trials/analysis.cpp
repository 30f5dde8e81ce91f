#include "vaw/trials/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "numerics.hpp"
#include "vaw/trials/procedure.hpp"

namespace vaw::trials {

using detail::normalCdf;

namespace {

// The spread is searched between 1 % and a factor e^3 of scale per standard deviation: below, the
// answers could not tell the difference (and perfectly separated answers would push it to zero); above,
// the curve is flat over any range a study tests.
constexpr double kMinLogSigma = -4.605170185988091;  // ln 0.01
constexpr double kMaxLogSigma = 1.0986122886681098;  // ln 3
// The PSE is searched this far (in ln scale) beyond the tested scales; an estimate at the edge is
// reported as not determined, an interval end beyond it as unbounded.
constexpr double kPseMargin = 1.0;
constexpr double kIntervalMargin = 3.0;
constexpr int kPseGrid = 60;

struct Level {
  double x;  // ln scale
  int n;
  int k;  // judged faster
};

double negLogLik(const std::vector<Level>& levels, double mu, double logSigma, double lapse) {
  const double inv = std::exp(-logSigma);
  double nll = 0.0;
  for (const auto& l : levels) {
    const double p = lapse + (1.0 - 2.0 * lapse) * normalCdf((l.x - mu) * inv);
    // Clamped so that lapse 0 and a far-off answer give a large finite penalty, not infinity.
    nll -= l.k * std::log(std::max(p, 1e-300)) + (l.n - l.k) * std::log(std::max(1.0 - p, 1e-300));
  }
  return nll;
}

struct Profile {
  double logSigma;
  double nll;
};

Profile profileAt(const std::vector<Level>& levels, double mu, double lapse) {
  const auto f = [&](double ls) { return negLogLik(levels, mu, ls, lapse); };
  const double ls = detail::goldenMinimize(f, kMinLogSigma, kMaxLogSigma, 1e-6);
  return {ls, f(ls)};
}

double logMeanInterval(const std::vector<double>& logs, double confidence, Interval& interval, double& sd) {
  const auto n = static_cast<double>(logs.size());
  double mean = 0.0;
  for (double y : logs) mean += y;
  mean /= n;
  double ss = 0.0;
  for (double y : logs) ss += (y - mean) * (y - mean);
  sd = std::sqrt(ss / (n - 1.0));
  const double half = detail::studentTQuantile(0.5 + 0.5 * confidence, n - 1.0) * sd / std::sqrt(n);
  interval = {std::exp(mean - half), std::exp(mean + half)};
  return mean;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<ScaleSummary> summarize(const std::vector<const Record*>& records) {
  std::map<double, std::pair<ScaleSummary, std::vector<double>>> by;
  for (const Record* r : records) {
    const bool setting = std::holds_alternative<Setting>(r->answer.response);
    const double s = setting ? std::get<Setting>(r->answer.response).scale : r->trial.scale;
    auto& [sum, times] = by[s];
    sum.scale = s;
    ++sum.trials;
    if (!setting && judgedFaster(*r)) ++sum.faster;
    if (r->answer.measures.caught) ++sum.caught;
    if (r->answer.measures.regraspTime_s) times.push_back(*r->answer.measures.regraspTime_s);
  }
  std::vector<ScaleSummary> out;
  for (auto& [s, entry] : by) {
    if (!entry.second.empty()) entry.first.medianRegrasp_s = median(entry.second);
    out.push_back(entry.first);
  }
  return out;
}

std::string conditionKey(const Design& d) {
  std::ostringstream k;
  k.precision(17);
  k << name(d.scenario) << '|' << name(d.motion) << '|' << name(d.question.answers);
  if (d.question.answers == AnswerKind::TwoInterval) k << '|' << d.question.referenceScale;
  if (d.viewing)
    k << '|' << d.viewing->geometry.distance_m << '|' << d.viewing->geometry.fallHeight_m << '|' << d.viewing->limits.pitchRate_deg_s
      << '|' << d.viewing->limits.yawRate_deg_s << '|' << d.viewing->limits.acceleration_deg_s2.value_or(-1.0);
  return k.str();
}

}  // namespace

double psychometric(double scale, double pse, double sigmaLog, double lapse) {
  return lapse + (1.0 - 2.0 * lapse) * normalCdf((std::log(scale) - std::log(pse)) / sigmaLog);
}

PsychometricFit fitPsychometric(const std::vector<Judged>& data, const AnalysisOptions& options) {
  PsychometricFit fit;
  fit.trials = static_cast<int>(data.size());
  fit.lapse = options.lapse;
  std::map<double, Level> by;
  int faster = 0;
  for (const auto& d : data) {
    auto& l = by.try_emplace(d.scale, Level{std::log(d.scale), 0, 0}).first->second;
    ++l.n;
    l.k += d.faster ? 1 : 0;
    faster += d.faster ? 1 : 0;
  }
  std::vector<Level> levels;
  for (const auto& [s, l] : by) levels.push_back(l);
  if (data.empty()) {
    fit.problem = "no judgements";
    return fit;
  }
  if (levels.size() < 2) {
    fit.problem = "every trial at one scale: no curve can be fitted";
    return fit;
  }
  // Which side of the tested scales the PSE lies on is what the experimenter needs to mend the design.
  const auto beyond = [&](bool above) {
    std::ostringstream o;
    o.precision(3);
    o << "the PSE lies " << (above ? "above " : "below ") << std::exp(above ? levels.back().x : levels.front().x) << ", the "
      << (above ? "highest" : "lowest") << " scale tested: add " << (above ? "higher" : "lower") << " scales to the design";
    return o.str();
  };
  if (faster == 0 || faster == fit.trials) {
    fit.problem = std::string("every answer ") + (faster == 0 ? "\"slower\": " : "\"faster\": ") + beyond(faster == 0);
    return fit;
  }
  const double lapse = options.lapse;
  const auto profile = [&](double mu) { return profileAt(levels, mu, lapse).nll; };
  // The profile over the PSE can have flat stretches where answers are perfectly separated, so a grid
  // brackets the best region before the golden section refines it.
  const double lo = levels.front().x - kPseMargin, hi = levels.back().x + kPseMargin;
  const double h = (hi - lo) / (kPseGrid - 1);
  int best = 0;
  double bestValue = profile(lo);
  for (int i = 1; i < kPseGrid; ++i)
    if (const double v = profile(lo + h * i); v < bestValue) {
      bestValue = v;
      best = i;
    }
  const double mu = detail::goldenMinimize(profile, lo + h * std::max(best - 1, 0), lo + h * std::min(best + 1, kPseGrid - 1), 1e-9);
  const Profile atBest = profileAt(levels, mu, lapse);
  fit.pse = std::exp(mu);
  fit.sigmaLog = std::exp(atBest.logSigma);
  fit.logLikelihood = -atBest.nll;
  if (best == 0 || best == kPseGrid - 1) {
    fit.problem = "the answers do not turn between the scales tested: " + beyond(best != 0);
    return fit;
  }
  // Profile-likelihood interval: every PSE whose profile deviance is within the chi-square(1) quantile.
  const double cut = atBest.nll + 0.5 * detail::chiSquare1Quantile(options.confidence);
  const auto excess = [&](double m) { return profile(m) - cut; };
  const auto end = [&](double direction) {
    const double limit = (direction < 0 ? levels.front().x : levels.back().x) + direction * kIntervalMargin;
    double inside = mu;
    for (double m = mu + direction * h;; m += direction * h) {
      if (direction * (m - limit) > 0) return direction < 0 ? 0.0 : std::numeric_limits<double>::infinity();
      if (excess(m) > 0) return std::exp(detail::bisectRoot(excess, std::min(inside, m), std::max(inside, m), 1e-7));
      inside = m;
    }
  };
  fit.pseInterval = {end(-1.0), end(+1.0)};
  fit.ok = true;
  return fit;
}

SettingsEstimate estimateSettings(const std::vector<double>& settings, const AnalysisOptions& options) {
  SettingsEstimate e;
  e.settings = static_cast<int>(settings.size());
  if (settings.size() < 2) {
    e.problem = "fewer than two settings: no interval";
    return e;
  }
  std::vector<double> logs;
  for (double s : settings) logs.push_back(std::log(s));
  e.geometricMean = std::exp(logMeanInterval(logs, options.confidence, e.meanInterval, e.sdLog));
  std::vector<double> sorted = settings;
  std::sort(sorted.begin(), sorted.end());
  e.median = median(sorted);
  // The k-th smallest and k-th largest settings bound the median with coverage 1 - 2 P(Bin(n, 1/2) < k);
  // the largest k that reaches the confidence, or the extremes when none does.
  const int n = e.settings;
  int k = 1;
  while (k + 1 <= n / 2 && 1.0 - 2.0 * detail::binomialHalfCdf(k, n) >= options.confidence) ++k;
  e.medianInterval = {sorted[static_cast<std::size_t>(k - 1)], sorted[static_cast<std::size_t>(n - k)]};
  e.medianCoverage = 1.0 - 2.0 * detail::binomialHalfCdf(k - 1, n);
  e.ok = true;
  return e;
}

std::optional<double> ParticipantResult::estimate() const {
  if (fit && fit->ok) return fit->pse;
  if (settings && settings->ok) return settings->geometricMean;
  return std::nullopt;
}

Interval ParticipantResult::interval() const {
  if (fit && fit->ok) return fit->pseInterval;
  if (settings && settings->ok) return settings->meanInterval;
  return {};
}

std::vector<ConditionAnalysis> analyze(const std::vector<ResultsFile>& files, const AnalysisOptions& options) {
  // Condition, then participant, in the order they first appear.
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::vector<const ResultsFile*>>>>> groups;
  for (const auto& f : files) {
    const std::string key = conditionKey(f.design);
    auto c = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == key; });
    if (c == groups.end()) c = groups.insert(groups.end(), {key, {}});
    auto p = std::find_if(c->second.begin(), c->second.end(), [&](const auto& g) { return g.first == f.design.participant; });
    if (p == c->second.end()) p = c->second.insert(c->second.end(), {f.design.participant, {}});
    p->second.push_back(&f);
  }

  std::vector<ConditionAnalysis> out;
  for (const auto& [key, participants] : groups) {
    ConditionAnalysis ca;
    const Design& d0 = participants.front().second.front()->design;
    ca.condition = {d0.scenario, d0.motion, d0.question.answers,
                    d0.question.answers == AnswerKind::TwoInterval ? std::optional<double>(d0.question.referenceScale) : std::nullopt,
                    d0.viewing};
    if (d0.viewing) ca.predicted = human::recommendScale(d0.viewing->geometry, d0.viewing->limits);
    std::vector<Judged> everyone;
    std::vector<const Record*> allRecords;
    for (const auto& [participant, pfiles] : participants) {
      ParticipantResult pr;
      pr.participant = participant;
      std::vector<Judged> judged;
      std::vector<double> settings;
      std::vector<const Record*> records;
      for (const ResultsFile* f : pfiles) {
        pr.files.push_back(f->path.string());
        pr.methods.emplace_back(methodName(f->design.method));
        for (const auto& r : f->records) {
          records.push_back(&r);
          if (const auto* s = std::get_if<Setting>(&r.answer.response)) settings.push_back(s->scale);
          else judged.push_back({r.trial.scale, judgedFaster(r)});
        }
        if (std::holds_alternative<Staircase>(f->design.method)) {
          // Replaying the answers gives the reversals; the first two come while the steps are large.
          Procedure replay(f->design);
          for (const auto& r : f->records) replay.answer(r.answer);
          for (const auto& rev : replay.reversals()) {
            if (rev.size() <= 2) continue;
            double sum = 0.0;
            for (std::size_t i = 2; i < rev.size(); ++i) sum += std::log(rev[i]);
            pr.reversalMeans.push_back(std::exp(sum / static_cast<double>(rev.size() - 2)));
          }
        }
      }
      pr.trials = static_cast<int>(records.size());
      std::vector<double> times;
      for (const Record* r : records) {
        pr.caught += r->answer.measures.caught ? 1 : 0;
        if (r->answer.measures.regraspTime_s) times.push_back(*r->answer.measures.regraspTime_s);
      }
      if (!times.empty()) pr.medianRegrasp_s = median(times);
      pr.perScale = summarize(records);
      if (d0.question.answers == AnswerKind::Setting) pr.settings = estimateSettings(settings, options);
      else pr.fit = fitPsychometric(judged, options);
      if (!pr.estimate()) {
        std::ostringstream note;
        note << "participant " << participant << ": no estimate: " << (pr.fit ? pr.fit->problem : pr.settings->problem);
        // With two intervals "slower" reads as the participant's own fall; say it in the question's terms.
        if (d0.question.answers == AnswerKind::TwoInterval)
          note << " (\"slower\" is a trial whose reference, scale " << d0.question.referenceScale
               << ", was judged the faster; the PSE is the scale that looks as fast as the reference)";
        ca.notes.push_back(note.str());
      }
      everyone.insert(everyone.end(), judged.begin(), judged.end());
      allRecords.insert(allRecords.end(), records.begin(), records.end());
      ca.participants.push_back(std::move(pr));
    }
    ca.perScale = summarize(allRecords);
    if (!everyone.empty()) ca.allAnswersFit = fitPsychometric(everyone, options);
    std::vector<const ParticipantResult*> estimated;
    for (const auto& p : ca.participants)
      if (p.estimate()) estimated.push_back(&p);
    if (estimated.size() == 1) {
      ca.pooled = Pooled{1, *estimated.front()->estimate(), estimated.front()->interval()};
    } else if (estimated.size() > 1) {
      std::vector<double> logs;
      for (const auto* p : estimated) logs.push_back(std::log(*p->estimate()));
      Pooled pooled;
      pooled.participants = static_cast<int>(logs.size());
      double sd = 0.0;
      pooled.estimate = std::exp(logMeanInterval(logs, options.confidence, pooled.interval, sd));
      ca.pooled = pooled;
    }
    out.push_back(std::move(ca));
  }
  return out;
}

}  // namespace vaw::trials
