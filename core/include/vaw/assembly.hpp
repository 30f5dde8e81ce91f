#pragma once
// The loaded, validated assembly: what the rest of vaw works on. SI units, world frame z up.
// Parts are referred to across layers by PartId (their index), never by pointer.
#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "vaw/categories.hpp"
#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/mass_properties.hpp"
#include "vaw/mesh.hpp"
#include "vaw/units.hpp"

namespace vaw {

using PartId = std::size_t;

struct Material {
  std::string name;
  std::optional<double> density;  // kg/m^3
  double staticFriction = 0.3;    // f_s
  double kineticFriction = 0.2;   // f_d <= f_s
  double rotationalFriction = 0.0; // f_r, N m s (viscous torque = f_r * omega)
  Eigen::Vector3f color{0.7f, 0.7f, 0.72f};
};

// Brep: the exact boundary representation of a CAD file (docs/step.md).
enum class MassSource { Mesh, PropertyFile, Brep };

struct Part {
  PartId id = 0;
  std::string name;
  std::shared_ptr<const TriMesh> mesh;   // part frame, metres
  std::string shapeSource;               // mesh path or primitive description
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // part frame -> world
  std::optional<Eigen::Isometry3d> finalPose;              // assembled pose, world
  std::string material;
  MassProperties mass;                   // the properties vaw uses
  MassSource massSource = MassSource::Mesh;
  std::optional<MassProperties> meshMass;      // computed from mesh and density, when possible
  std::optional<MassProperties> fileMass;      // from the property file or the CAD file's B-rep, when given
  std::optional<MassComparison> disagreement;  // when both exist
  Principal principal;
  double extent = 0.0;                   // largest principal dimension, m
  CategoryResult category;
  std::filesystem::path propertyFile;
  std::optional<Eigen::Vector3f> color;    // the CAD file's colour; else the material's
  std::shared_ptr<const CadSolid> cad;     // the CAD solid (exact faces), shared between instances
  std::string product;                     // the CAD product's own name (the part's is the instance's)
  // A bought-in unit (a bearing, a motor, a servo: a CAD sub-assembly handled as one rigid part,
  // docs/step.md, "Units"): the names of the parts it holds and why it is one; empty for a part.
  std::vector<std::string> unitMembers;
  std::string unitReason;
};

struct EnvironmentObject {
  std::string name;
  std::string kind;  // "table", "floor", "fixture"
  std::shared_ptr<const TriMesh> mesh;
  std::string shapeSource;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3f color{0.55f, 0.45f, 0.35f};
  // The room's floor a scene did not declare (sim::addDefaultFloor): not part of the scene's content hash,
  // so that sessions recorded before there was a floor still match their scene.
  bool implied = false;
};

// Initialised, so a constraint's geometry of the other kind (a mate's axes) holds no stray bits.
struct Plane { Eigen::Vector3d point = Eigen::Vector3d::Zero(); Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); };  // normal unit length
struct Axis { Eigen::Vector3d point = Eigen::Vector3d::Zero(); Eigen::Vector3d direction = Eigen::Vector3d::UnitZ(); }; // direction unit length

// An assembly constraint between a part and its partner (the base unless `partner` names another part),
// geometry in each one's own frame: the "base" members hold the partner's geometry.
struct Constraint {
  enum class Type { Mate, Align, Insert };
  Type type = Type::Mate;
  std::string name;
  PartId part = 0;
  std::optional<PartId> partner;   // empty: the base
  Plane partPlane{}, basePlane{};  // Mate (normals opposed) / Align (normals equal)
  Axis partAxis{}, baseAxis{};     // Insert
  double offset = 0.0;             // m, signed distance between the planes (Mate/Align)
  // What recognition measured, for constraints found in the geometry (docs/step.md).
  struct Found {
    // How an insert's shaft sits in its bore: with play (or none), or larger by design: a thread modelled
    // at its tap drill, a press fit (vaw/fits.hpp). A designed interference is a fit, not a collision.
    enum class Fit { Clearance, Threaded, Press };
    double partRadius = 0.0, partnerRadius = 0.0;  // m, Insert
    double clearance = 0.0;                        // m, radial, Insert
    double overlap = 0.0;  // m^2 of face overlap (Mate), m of axial overlap (Insert)
    bool fromSpline = false;  // one of the faces was a B-spline recognised as a plane or cylinder
    Fit fit = Fit::Clearance;
    double interference = 0.0;  // m, radial: the shaft's radius less the bore's (Threaded, Press)
    std::string thread;         // Threaded: "M6", "1/4-20 UNC"
    // Where a head sits as it goes home: in a counterbore, a larger bore on the same axis with its floor
    // under the head; in a countersink, its cone on the hole's cone (docs/step.md, "Fits as designers model
    // them").
    enum class Seat { None, Counterbore, Countersink };
    Seat seat = Seat::None;
    double seatRadius = 0.0;  // m: the counterbore's radius, the countersink's largest
    double seatAngle = 0.0;   // rad: a countersink's half angle (45 degrees for ISO 10642's 90 degree head)
    // A key fit (Mate): one part's two parallel faces between two faces of the other, this far apart (m; 0:
    // none): a key in its keyway or in a hub's slot, free only along those faces. The mate is one side.
    double keyWidth = 0.0;
  };
  std::optional<Found> found;
  // The direction the part comes home from, in the partner's frame: it travels along -homeDirection
  // into its final pose (along the axis for an insert, onto the plane for a mate).
  Eigen::Vector3d homeDirection = Eigen::Vector3d::UnitZ();
  bool accepted = false;  // the user confirmed it (Constraints panel); saved with the scene
};
std::string_view name(Constraint::Type t);
std::string_view name(Constraint::Found::Fit f);
std::string_view name(Constraint::Found::Seat s);

// A tool that lifts parts too heavy for the hands (docs/scene-format.md, "Tools"): a hook on a vertical
// line at a fixed (x, y) that rises, lowers and turns about the vertical, and takes a tool-lifted part
// within its reach.
struct Hoist {
  std::string name = "hoist";
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, world x, y of the vertical line
  double reach = 0.05;    // m, from the hook to a part's world bounds
  double lowest = 0.0;    // m, world z range of the hook
  double highest = 2.0;
  double height = 1.0;    // m, where the hook hangs at load
};

// The three friction coefficients of a material, or of one part's override of its material's.
struct FrictionValues {
  double staticFriction = 0.3;      // f_s
  double kineticFriction = 0.2;     // f_d <= f_s
  double rotationalFriction = 0.0;  // f_r, N m s
  friend bool operator==(const FrictionValues&, const FrictionValues&) = default;
};

// The tuning a scene file carries in its "settings" block (docs/scene-format.md, version 2): what the
// simulation starts with when the scene is opened. Material friction set there is already in
// Assembly::materials; what is unset here takes the simulation's defaults.
struct SceneSettings {
  std::optional<double> rate;  // Hz
  std::optional<double> freeFlightScale, slideScale, rotationScale;
  std::optional<std::string> rotationMethod;  // a method name (dynamics/integrators.hpp)
  std::optional<bool> placeAtRest;            // sim::Settings::placeAtRest; set for CAD assemblies
  std::map<PartId, FrictionValues> partFriction;  // per-part overrides of their material's friction
};

// The scene tree as the file wrote it: groups, parts, environment objects.
struct TreeNode {
  // MeshNode children of a Part are the nodes of its mesh file (names only; geometry is merged).
  enum class Kind { Assembly, Group, Part, Environment, MeshNode };
  Kind kind = Kind::Group;
  std::string name;
  std::size_t index = 0;  // PartId for Part, environment index for Environment
  std::vector<TreeNode> children;
};

struct Assembly {
  std::string name;
  std::filesystem::path source;
  // Set when the parts come from a CAD file (STEP): that file and the hash of its bytes when it was read
  // (docs/scene-format.md, "cad"). `source` is then the CAD file itself or the scene that refers to it.
  std::filesystem::path cadFile;
  std::string cadHash;
  // How a CAD assembly stands on the table (docs/step.md, "Which way is up"): the choice ("auto" or a file
  // axis such as "+y") and the file's direction that points up as a result.
  std::string cadUp = "auto";
  Eigen::Vector3d cadUpAxis = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d cadTurn = Eigen::Matrix3d::Identity();  // the file's directions -> the table's, as loaded
  // The user's choices of units (docs/step.md, "Units"): sub-assemblies, by instance name, handled as parts
  // although they form a unit, and handled as one unit although they come apart; saved with the scene.
  std::set<std::string> cadSplit, cadJoin;
  LengthUnit units = LengthUnit::Metre;
  std::map<std::string, Material> materials;
  std::vector<Part> parts;
  std::optional<PartId> base;
  std::string baseReason;  // why that part is the base, for people (a CAD assembly's; empty when a file names it)
  std::vector<EnvironmentObject> environment;
  std::vector<Constraint> constraints;
  std::vector<Hoist> hoists;
  SceneSettings settings;
  TreeNode tree;
  Diagnostics warnings;
  CategorySettings categorySettings;

  [[nodiscard]] std::optional<PartId> findPart(std::string_view partName) const;
  [[nodiscard]] std::size_t totalTriangles() const;
  [[nodiscard]] Eigen::AlignedBox3d worldBounds() const;
};

// A hash of what a simulation of the assembly depends on: materials, parts (name, mesh, poses, mass,
// category), friction settings, base, environment and constraints. Sessions keep it (Scene::contentHash)
// to refuse a replay on a changed scene; a STEP file's kept answer of who goes first is filed under it.
std::uint64_t contentHash(const Assembly& a);

}  // namespace vaw
