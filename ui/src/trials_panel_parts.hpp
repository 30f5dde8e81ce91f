#pragma once
// What the trials panel's files share: text and path conversions, and the panel's widths.
#include <QFile>
#include <QString>
#include <filesystem>
#include <string_view>

#include "format.hpp"

namespace vaw::ui::detail {

// Wide enough for the analysis table and a readable chart; during a session the 3D view needs the room.
inline constexpr int kAnalysisWidth = 720, kSessionWidth = 420;

using format::str;
inline std::filesystem::path fsPath(const QString& p) { return std::filesystem::path(QFile::encodeName(p).toStdString()); }
inline QString qPath(const std::filesystem::path& p) { return QFile::decodeName(p.string().c_str()); }

}  // namespace vaw::ui::detail
