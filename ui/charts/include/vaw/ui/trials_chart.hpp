#pragma once
#include <QtCharts/QChart>
#include <filesystem>
#include <vector>

#include "vaw/trials/analysis.hpp"

namespace vaw::ui {

// Answers against gravity scale for one condition: the share judged faster at each scale (or, for
// adjustment, the share of settings at or below it) with the fitted curve, the pooled estimate and its
// interval as a band, each participant's estimate, and the head-demand model's recommended scale.
QChart* makeTrialsChart(const trials::ConditionAnalysis& analysis);

// Writes one PNG per condition: `png` for the first, `<stem>-2.png`, ... for the others. Creates a
// QApplication (offscreen when there is no display) if none exists. Returns the files written.
std::vector<std::filesystem::path> writeTrialsCharts(const std::vector<trials::ConditionAnalysis>& analyses,
                                                     const std::filesystem::path& png, int argc, char** argv);

}  // namespace vaw::ui
