#include "vaw/trials/simulated_participant.hpp"

#include <algorithm>
#include <cmath>

#include "../base/json_node.hpp"
#include "numerics.hpp"
#include "random.hpp"

namespace vaw::trials {

using vaw::detail::Json;
using vaw::detail::Node;

ParticipantModel loadParticipantModel(const std::filesystem::path& file) {
  const Json j = vaw::detail::readJsonFile(file);
  const std::string f = file.string();
  const Node root(j, "", f);
  root.requireObject();
  const Node format = root.get("format");
  if (format.string() != "vaw-simulated-participant") format.fail("\"vaw-simulated-participant\"");
  const Node version = root.get("version");
  if (version.integer() != 1) version.fail("version 1 (the version this vaw reads)");
  root.allowOnly({"format", "version", "pse", "sigma_log", "lapse", "adjust_sd_log", "start_pull", "catch_scale",
                  "catch_sigma_log", "regrasp_median_s", "regrasp_sd_log", "seed"});
  ParticipantModel m;
  m.pse = root.get("pse").positive();
  m.sigmaLog = root.get("sigma_log").positive();
  if (const auto n = root.opt("lapse")) {
    m.lapse = n->nonNegative();
    if (m.lapse >= 0.5) n->fail("a lapse rate below 0.5");
  }
  if (const auto n = root.opt("adjust_sd_log")) m.adjustSdLog = n->nonNegative();
  if (const auto n = root.opt("start_pull")) {
    m.startPull = n->nonNegative();
    if (m.startPull > 1.0) n->fail("a weight between 0 and 1");
  }
  if (const auto n = root.opt("catch_scale")) m.catchScale = n->positive();
  if (const auto n = root.opt("catch_sigma_log")) m.catchSigmaLog = n->positive();
  if (const auto n = root.opt("regrasp_median_s")) m.regraspMedian_s = n->positive();
  if (const auto n = root.opt("regrasp_sd_log")) m.regraspSdLog = n->nonNegative();
  const Node seed = root.get("seed");
  if (!seed.json().is_number_unsigned()) seed.fail("a non-negative integer");
  m.seed = seed.json().get<std::uint64_t>();
  return m;
}

double probabilityFaster(const ParticipantModel& m, double scale) {
  return m.lapse + (1.0 - 2.0 * m.lapse) * detail::normalCdf((std::log(scale) - std::log(m.pse)) / m.sigmaLog);
}

Answer simulateAnswer(const ParticipantModel& m, const Trial& trial) {
  detail::Random rng(m.seed, detail::Stream::Participant, static_cast<std::uint64_t>(trial.index));
  Answer a;
  if (trial.adjustable) {
    const double wanted = std::log(m.pse) + m.adjustSdLog * rng.normal();
    const double set = (1.0 - m.startPull) * wanted + m.startPull * std::log(trial.scale);
    a.response = Setting{std::clamp(std::exp(set), trial.adjustable->min, trial.adjustable->max)};
  } else {
    const bool faster = rng.uniform() < probabilityFaster(m, trial.scale);
    if (!trial.referenceScale) a.response = faster ? Judgement::TooFast : Judgement::TooSlow;
    else a.response = faster != trial.referenceFirst ? Judgement::First : Judgement::Second;
  }
  // For an adjustment the fall the participant last saw is at their setting.
  const double shown = trial.adjustable ? std::get<Setting>(a.response).scale : trial.scale;
  a.measures.caught = rng.uniform() < detail::normalCdf((std::log(m.catchScale) - std::log(shown)) / m.catchSigmaLog);
  if (a.measures.caught) a.measures.regraspTime_s = m.regraspMedian_s * std::exp(m.regraspSdLog * rng.normal());
  return a;
}

}  // namespace vaw::trials
