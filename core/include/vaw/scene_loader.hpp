#pragma once
// Reads a scene file (docs/scene-format.md) or a bare mesh file into a validated Assembly.
// All or nothing: on any error an InputError is thrown and nothing is half-loaded.
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw {

struct LoadOptions {
  CategorySettings categories = CategorySettings::defaults();
  // Units and density for a bare mesh file, which carries neither.
  LengthUnit bareMeshUnits = LengthUnit::Millimetre;
  double bareMeshDensity = 7850.0;  // kg/m^3, steel
  // Relative disagreement between property file and mesh above which a warning is raised.
  double massDisagreementWarning = 0.01;
  // Tessellation and time limit for CAD files (STEP).
  ImportOptions import;
  // The base of a CAD assembly, by part name; empty: the part it stands on (chooseBase).
  std::optional<std::string> cadBase;
  // Which way a CAD assembly stands: "auto" (the base on its most stable face) or the file's axis that
  // points up ("+y", ...); empty: what the scene saved, else "auto".
  std::optional<std::string> cadUp;
  // CAD sub-assemblies, by their instance names: handled as parts although they form a unit, and handled as
  // one unit although they come apart (docs/step.md, "Units").
  std::set<std::string> cadSplit, cadJoin;
  // Where a CAD file's open spends its time, stage by stage (seconds), when given: the reader, units,
  // parts and meshes, recognition, the base, who goes first, the layout (vaw-sim inspect --timings).
  std::vector<std::pair<std::string, double>>* timings = nullptr;
};

// Version 2 adds "tools", version 3 "cad" and constraints between parts ("partner"); earlier files still load.
inline constexpr int kSceneFormatVersion = 3;

Assembly loadScene(const std::filesystem::path& file, const ImporterRegistry& importers,
                   const LoadOptions& options = {}, const ProgressFn& progress = {});

// A mesh file opened on its own becomes an assembly of one part per top-level node.
Assembly loadMeshFile(const std::filesystem::path& file, const ImporterRegistry& importers,
                      const LoadOptions& options = {}, const ProgressFn& progress = {});

// Picks loadScene for .json/.vaw files and loadMeshFile for everything an importer reads.
Assembly loadAny(const std::filesystem::path& file, const ImporterRegistry& importers,
                 const LoadOptions& options = {}, const ProgressFn& progress = {});

}  // namespace vaw
