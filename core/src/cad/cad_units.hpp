#pragma once
// Bought-in units (docs/step.md, "Units"): a CAD sub-assembly whose parts cannot be taken apart on their
// own (a part trapped between the others: a bearing's balls between its rings, a motor's rotor in its
// housing, a servo's shaft) is put together, carried and placed as one rigid part. Private to the core.
#include <map>
#include <set>
#include <string>

#include "../input/load_detail.hpp"
#include "vaw/importer.hpp"

namespace vaw::detail {

// Replaces in `root`'s tree, innermost first, every sub-assembly that is a unit, or that `join` names, and
// that `split` does not name, by one instance of a solid holding its parts' (shared by every instance of
// the same sub-assembly); the instance keeps its parts as children, for their names. Returns, per unit's
// name, why it is one.
// `import`: where the decisions are kept between sessions (ImportOptions::resultCache); `meshes`: the
// solids' checked meshes, shared with the parts made from them afterwards.
std::map<std::string, std::string> joinUnits(ImportedNode& root, const std::set<std::string>& split, const std::set<std::string>& join,
                                             const ImportOptions& import, SolidMeshes& meshes, const ProgressFn& progress = {});

}  // namespace vaw::detail
