#pragma once
#include <string>

namespace vaw::app {
// `vaw-sim export SESSION_OR_SCENE --out FILE.glb`: the scene and how its parts moved as glTF 2.0
// (docs/sharing.md). The options as parsed in vaw_sim.cpp.
struct ExportArgs {
  std::string input, out;
  bool order = false;        // a scene's planned order played, rather than the scene at rest
  double rate = 30.0;        // samples a second
  double stepSeconds = 1.0;  // each step of the order
  double toleranceMm = 0.1;  // a key is dropped where its neighbours' interpolation stays this close
};
int exportGltf(const ExportArgs& args);
}  // namespace vaw::app
