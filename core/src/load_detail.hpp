#pragma once
// Shared by the scene loader, the mesh import and the CAD assembly builder (private to the core's sources).
#include <algorithm>
#include <sstream>
#include <string>

#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh.hpp"

namespace vaw::detail {

// Welds, removes degenerate triangles (with a warning) and rejects meshes that are not a solid, naming
// `file`.
void validateSolid(TriMesh& mesh, const std::string& file, Diagnostics& warnings, const ProgressFn& progress);

// Calls the user's progress callback over a sub-range and turns a "stop" answer into LoadCancelled.
class Progress {
 public:
  explicit Progress(const ProgressFn& fn) : fn_(fn) {}
  void report(double fraction, const std::string& stage) const {
    if (fn_ && !fn_(std::clamp(fraction, 0.0, 1.0), stage)) throw LoadCancelled();
  }
  [[nodiscard]] ProgressFn sub(double from, double to) const {
    if (!fn_) return {};
    return [this, from, to](double f, const std::string& stage) {
      return fn_(from + (to - from) * std::clamp(f, 0.0, 1.0), stage);
    };
  }

 private:
  const ProgressFn& fn_;
};

inline std::string toString(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace vaw::detail
