#pragma once
// The scene a recorded session names, for the commands that replay one (clearance, sweep, export).
#include <filesystem>
#include <system_error>

#include "vaw/paths.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::app {

// As the session names it (a path or a bundled scene's name, resolveScenePath), else next to the session file.
inline std::filesystem::path sessionSceneFile(const sim::Session& session, const std::filesystem::path& sessionFile) {
  std::filesystem::path file = resolveScenePath(session.scene);
  std::error_code ec;
  if (!std::filesystem::exists(file, ec) && std::filesystem::path(session.scene).is_relative())
    file = sessionFile.parent_path() / session.scene;
  return file;
}

}  // namespace vaw::app
