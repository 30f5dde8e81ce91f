#pragma once
// Shared by the scene loader, the mesh import and the CAD assembly builder (private to the core's sources).
#include <algorithm>
#include <sstream>
#include <string>

#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh.hpp"

namespace vaw::detail {

// What validateSolid does with a mesh that stays open after repairMesh: a mesh file's part has nothing
// else to take its mass from, so it is refused; a CAD part's mass comes from its B-rep, so it is kept and
// the caller warns.
enum class OpenMesh { Refuse, Keep };

// Welds and mends the mesh (repairMesh) and rejects meshes that are not a solid, naming `file`. Returns
// the check after the repair (open only under OpenMesh::Keep). Triangles whose corners weld together are
// the mesher's or the file's noise and go without a word; what they leave open is refused or reported.
MeshCheck validateSolid(TriMesh& mesh, const std::string& file, const ProgressFn& progress, OpenMesh open = OpenMesh::Refuse);

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
