// Scene files (docs/scene-format.md), with no importer plugin: mesh references end in a named error.
#include "fuzz_support.hpp"
#include "vaw/scene_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const vaw::ImporterRegistry importers;
  try {
    (void)vaw::loadScene(vaw::fuzz::writeInput(data, size, "scene.vaw.json"), importers);
  } catch (const vaw::InputError&) {
  }
  return 0;
}
