#pragma once
// Where vaw finds its bundled resources and plugins. The build tree mirrors the install tree
// (bin/, lib/vaw/plugins/, share/vaw/), so both are found relative to the running executable.
#include <filesystem>
#include <vector>

namespace vaw {

std::filesystem::path executableDir();
// $VAW_RESOURCE_DIR if set, else <exe>/../share/vaw.
std::filesystem::path resourceDir();
// The scene the workbench opens when started without arguments.
std::filesystem::path defaultScenePath();

}  // namespace vaw
