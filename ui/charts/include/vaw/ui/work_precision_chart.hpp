#pragma once
#include <QtCharts/QChart>
#include <filesystem>
#include <string>
#include <vector>

#include "vaw/dynamics/work_precision.hpp"

namespace vaw::ui {

// Log-log work-precision chart of one scenario: CPU time per simulated second against the error,
// one line per method over the step rates, unstable points marked.
QChart* makeWorkPrecisionChart(const std::vector<dyn::Record>& records, const std::string& scenario);

// Writes work-precision-<scenario>.png and .svg into dir for every scenario in records. Creates a
// QApplication (offscreen when there is no display) if none exists. Returns the files written.
std::vector<std::filesystem::path> writeWorkPrecisionCharts(const std::vector<dyn::Record>& records,
                                                            const std::filesystem::path& dir, int argc, char** argv);

}  // namespace vaw::ui
