#pragma once
// Shared by the scene loader, the mesh import and the CAD assembly builder (private to the core's sources).
#include <algorithm>
#include <map>
#include <memory>
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

// Each CAD solid's mesh welded and checked once per open (validateSolid, open meshes kept), shared by
// every use: the test of a sub-assembly for a unit and the parts made from it then hold one mesh, so the
// collision hierarchy built for the first is handed to the second (CollisionWorld keeps it per living mesh).
class SolidMeshes {
 public:
  struct Checked {
    std::shared_ptr<const TriMesh> mesh;
    MeshCheck check;
  };
  // `file`: the file the solids come from, named with a solid's product in a refusal.
  explicit SolidMeshes(std::string file) : file_(std::move(file)) {}
  const Checked& of(const std::shared_ptr<const CadSolid>& solid);

 private:
  std::string file_;
  // Keeps each solid alive while its entry is keyed by its address.
  std::map<const CadSolid*, std::pair<std::shared_ptr<const CadSolid>, Checked>> done_;
};

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
