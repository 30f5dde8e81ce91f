#include "bundled.hpp"

#include <gtest/gtest.h>

#include "vaw/scene_loader.hpp"

namespace vaw::test {

const ImporterRegistry& importers() {
  static ImporterRegistry* registry = [] {
    auto* r = new ImporterRegistry();  // lives for the whole test program: plugins stay loaded
    for (const auto& p : r->loadPlugins(VAW_BUILD_PLUGIN_DIR)) ADD_FAILURE() << p;
    return r;
  }();
  EXPECT_FALSE(registry->importerNames().empty()) << "no importer plugin in " << VAW_BUILD_PLUGIN_DIR;
  return *registry;
}

std::filesystem::path resources() { return VAW_BUILD_RESOURCE_DIR; }

Assembly loadBundled(const std::string& sceneFile) { return loadScene(resources() / "scenes" / sceneFile, importers()); }

}  // namespace vaw::test
