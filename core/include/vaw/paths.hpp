#pragma once
// Where vaw finds its bundled resources and plugins. The build tree mirrors the install tree
// (bin/, lib/vaw/plugins/, share/vaw/), so both are found relative to the running executable.
#include <filesystem>
#include <string>
#include <vector>

namespace vaw {

std::filesystem::path executableDir();
// $VAW_RESOURCE_DIR if set, else <exe>/../share/vaw.
std::filesystem::path resourceDir();
// The scene the workbench opens when started without arguments.
std::filesystem::path defaultScenePath();

// A scene or mesh file named by the user (on a command line, or as a session's "scene"): the path as
// given when there is something there, else the bundled scene of that name (resourceDir()/scenes/NAME).
// When neither exists the path comes back as given, and loading it fails with an error that says where
// it looked (scenePlaces). Every entry point resolves names here: vaw-sim inspect and run, the workbench.
std::filesystem::path resolveScenePath(const std::filesystem::path& given);
// "looked at /abs/NAME and <resources>/scenes/NAME", for a name resolveScenePath did not find.
std::string scenePlaces(const std::filesystem::path& given);

// Where vaw keeps what it can compute again (the STEP reader's results): $VAW_CACHE_DIR when set ("off":
// nothing is kept, an empty path), else $XDG_CACHE_HOME/vaw, else $HOME/.cache/vaw (the user's settings
// are in $XDG_CONFIG_HOME/vaw, the XDG base directories' place for what must not be lost); empty when
// neither variable is set.
std::filesystem::path userCacheDir();

// What keeps `file` from being read as a regular file: "no such file", "a directory", "a loop of
// symbolic links", "not a regular file", or the system's reason; empty when nothing does. Never throws
// (a name too long for the system is a reason too).
std::string fileProblem(const std::filesystem::path& file);

}  // namespace vaw
