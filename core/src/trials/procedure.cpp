#include "vaw/trials/procedure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "numerics.hpp"
#include "random.hpp"

namespace vaw::trials {

using detail::Random;
using detail::Stream;

namespace {

// The QUEST grid spans the design's range in log scale; 401 points put neighbours about 1 % apart on
// the default range, far below any spread a participant shows.
constexpr int kQuestGrid = 401;

}  // namespace

std::string_view name(Judgement j) {
  switch (j) {
    case Judgement::TooFast: return "too-fast";
    case Judgement::TooSlow: return "too-slow";
    case Judgement::First: return "first";
    case Judgement::Second: return "second";
  }
  return "?";
}

bool judgedFaster(const Record& r) {
  const Judgement j = std::get<Judgement>(r.answer.response);
  if (j == Judgement::TooFast || j == Judgement::TooSlow) return j == Judgement::TooFast;
  // The trial's own fall is the interval that is not the reference.
  return (j == Judgement::First) != r.trial.referenceFirst;
}

Procedure::Procedure(Design design) : design_(std::move(design)) {
  if (const auto* c = std::get_if<ConstantStimuli>(&design_.method)) {
    for (int rep = 0; rep < c->repetitions; ++rep) {
      std::vector<double> block = c->scales;
      Random(design_.seed, Stream::Order, static_cast<std::uint64_t>(rep)).shuffle(block.begin(), block.end());
      order_.insert(order_.end(), block.begin(), block.end());
    }
  } else if (const auto* s = std::get_if<Staircase>(&design_.method)) {
    stairs_ = {StairState{s->startLow}, StairState{s->startHigh}};
    reversals_.resize(stairs_.size());
  } else if (const auto* q = std::get_if<Quest>(&design_.method)) {
    const double lo = std::log(q->range.min), hi = std::log(q->range.max), mu0 = std::log(q->priorScale);
    for (int i = 0; i < kQuestGrid; ++i) {
      const double x = lo + (hi - lo) * i / (kQuestGrid - 1);
      questGrid_.push_back(x);
      posterior_.push_back(-0.5 * (x - mu0) * (x - mu0) / (q->priorSdLog * q->priorSdLog));
    }
  }
  advance();
}

int Procedure::plannedTrials() const {
  return std::visit(
      [this](const auto& m) -> int {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, ConstantStimuli>) return static_cast<int>(order_.size());
        else if constexpr (std::is_same_v<T, Staircase>) return static_cast<int>(stairs_.size()) * m.maxTrials;
        else return m.trials;
      },
      design_.method);
}

Trial Procedure::makeTrial(double scale) const {
  Trial t;
  t.index = static_cast<int>(records_.size());
  t.scenario = design_.scenario;
  t.motion = design_.motion;
  t.scale = scale;
  t.blinded = design_.blind;
  if (design_.question.answers == AnswerKind::TwoInterval) {
    t.referenceScale = design_.question.referenceScale;
    t.referenceFirst = Random(design_.seed, Stream::TwoInterval, static_cast<std::uint64_t>(t.index)).uniform() < 0.5;
  }
  return t;
}

bool Procedure::stairDone(std::size_t k) const {
  const auto& s = std::get<Staircase>(design_.method);
  return stairs_[k].trials >= s.maxTrials ||
         (stairs_[k].trials >= s.minTrials && static_cast<int>(reversals_[k].size()) >= s.minReversals);
}

void Procedure::advance() {
  next_.reset();
  const auto index = records_.size();
  if (const auto* a = std::get_if<Adjustment>(&design_.method)) {
    if (index >= static_cast<std::size_t>(a->trials)) return;
    // Log-uniform start, so that starts above and below a preferred scale are equally likely in ratio.
    const double u = Random(design_.seed, Stream::Start, index).uniform();
    const double lo = std::log(a->start.min), hi = std::log(a->start.max);
    next_ = makeTrial(std::exp(lo + u * (hi - lo)));
    next_->adjustable = a->range;
  } else if (std::holds_alternative<ConstantStimuli>(design_.method)) {
    if (index < order_.size()) next_ = makeTrial(order_[index]);
  } else if (std::holds_alternative<Staircase>(design_.method)) {
    // Each round asks every unfinished staircase once, in an order drawn for that round, so the
    // participant cannot tell from the sequence which staircase is asking.
    if (round_.empty()) {
      for (std::size_t k = 0; k < stairs_.size(); ++k)
        if (!stairDone(k)) round_.push_back(static_cast<int>(k));
      if (round_.empty()) return;
      Random(design_.seed, Stream::Interleave, static_cast<std::uint64_t>(roundIndex_++)).shuffle(round_.begin(), round_.end());
    }
    const int k = round_.front();
    next_ = makeTrial(stairs_[static_cast<std::size_t>(k)].scale);
    next_->staircase = k;
  } else if (const auto* q = std::get_if<Quest>(&design_.method)) {
    if (index >= static_cast<std::size_t>(q->trials)) return;
    const double top = *std::max_element(posterior_.begin(), posterior_.end());
    double sum = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < posterior_.size(); ++i) {
      const double w = std::exp(posterior_[i] - top);
      sum += w;
      mean += w * questGrid_[i];
    }
    // At the mean alone every trial would sit on the 50 % point, where the answers say nothing about
    // the slope; the fit then comes out too steep and its interval too narrow. A third of the trials
    // each go one assumed spread below and above it, drawn per trial.
    const double offset = static_cast<double>(Random(design_.seed, Stream::QuestOffset, index).below(3)) - 1.0;
    const double x = std::clamp(mean / sum + offset * q->sigmaLog, questGrid_.front(), questGrid_.back());
    next_ = makeTrial(std::exp(x));
  }
}

void Procedure::check(const Answer& a) const {
  if (!next_) throw std::invalid_argument("trials: the session is complete; no trial awaits an answer");
  if (design_.question.answers == AnswerKind::Setting) {
    const auto* s = std::get_if<Setting>(&a.response);
    if (!s) throw std::invalid_argument("trials: this design asks for a setting, not a judgement");
    if (!(s->scale >= next_->adjustable->min && s->scale <= next_->adjustable->max))
      throw std::invalid_argument("trials: setting " + std::to_string(s->scale) + " lies outside the adjustable range");
  } else {
    const auto* j = std::get_if<Judgement>(&a.response);
    if (!j) throw std::invalid_argument("trials: this design asks for a judgement, not a setting");
    const bool twoInterval = design_.question.answers == AnswerKind::TwoInterval;
    const bool isInterval = *j == Judgement::First || *j == Judgement::Second;
    if (twoInterval != isInterval)
      throw std::invalid_argument(twoInterval ? "trials: a two-interval trial is answered \"first\" or \"second\""
                                              : "trials: this trial is answered \"too-fast\" or \"too-slow\"");
  }
  if (const auto& t = a.measures.regraspTime_s; t && !(std::isfinite(*t) && *t >= 0.0))
    throw std::invalid_argument("trials: a re-grasp time is a finite number of seconds >= 0");
}

void Procedure::answer(const Answer& a) {
  check(a);
  records_.push_back({*next_, a});
  const Record& r = records_.back();
  if (const auto* s = std::get_if<Staircase>(&design_.method)) {
    const auto k = static_cast<std::size_t>(*r.trial.staircase);
    round_.erase(round_.begin());
    StairState& st = stairs_[k];
    ++st.trials;
    const bool faster = judgedFaster(r);
    st.run = faster ? std::max(st.run, 0) + 1 : std::min(st.run, 0) - 1;
    int step = 0;
    if (st.run >= s->nDown) step = -1;
    else if (st.run <= -s->nUp) step = +1;
    if (step != 0) {
      st.run = 0;
      if (st.direction != 0 && step != st.direction) reversals_[k].push_back(r.trial.scale);
      st.direction = step;
      const std::size_t i = std::min(reversals_[k].size(), s->stepFactors.size() - 1);
      const double f = s->stepFactors[i];
      st.scale = std::clamp(step > 0 ? st.scale * f : st.scale / f, s->range.min, s->range.max);
    }
  } else if (const auto* q = std::get_if<Quest>(&design_.method)) {
    const double x = std::log(r.trial.scale);
    const bool faster = judgedFaster(r);
    for (std::size_t i = 0; i < posterior_.size(); ++i) {
      const double p = q->lapse + (1.0 - 2.0 * q->lapse) * detail::normalCdf((x - questGrid_[i]) / q->sigmaLog);
      posterior_[i] += std::log(std::max(faster ? p : 1.0 - p, 1e-300));
    }
  }
  advance();
}

}  // namespace vaw::trials
