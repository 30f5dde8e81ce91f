#include "vaw/sim/scene_file.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"

namespace vaw::sim {

namespace {

using Ordered = nlohmann::ordered_json;

Ordered frictionJson(const FrictionValues& f) {
  return Ordered{{"static", f.staticFriction}, {"kinetic", f.kineticFriction}, {"rotational", f.rotationalFriction}};
}

// A relative path written for `from`'s folder, rewritten for `to`'s.
std::string rebase(const std::string& path, const std::filesystem::path& from, const std::filesystem::path& to) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || from == to) return path;
  const std::filesystem::path absolute = (from / p).lexically_normal();
  const std::filesystem::path relative = absolute.lexically_relative(to);
  return relative.empty() ? absolute.string() : relative.generic_string();
}

void rebaseNodes(Ordered& list, const std::filesystem::path& from, const std::filesystem::path& to) {
  if (!list.is_array()) return;
  for (Ordered& item : list) {
    if (!item.is_object()) continue;
    for (const char* key : {"mesh", "properties"})
      if (item.contains(key) && item[key].is_string()) item[key] = rebase(item[key].get<std::string>(), from, to);
    if (item.contains("children")) rebaseNodes(item["children"], from, to);
  }
}

Ordered vec(const Eigen::Vector3d& v) { return Ordered::array({v.x(), v.y(), v.z()}); }

Ordered constraintJson(const Assembly& a, const Constraint& c) {
  Ordered j{{"type", std::string(name(c.type))}, {"name", c.name}, {"part", a.parts[c.part].name}};
  if (c.partner) j["partner"] = a.parts[*c.partner].name;
  if (c.type == Constraint::Type::Insert) {
    j["part_axis"] = Ordered{{"point", vec(c.partAxis.point)}, {"direction", vec(c.partAxis.direction)}};
    j["base_axis"] = Ordered{{"point", vec(c.baseAxis.point)}, {"direction", vec(c.baseAxis.direction)}};
  } else {
    j["part_plane"] = Ordered{{"point", vec(c.partPlane.point)}, {"normal", vec(c.partPlane.normal)}};
    j["base_plane"] = Ordered{{"point", vec(c.basePlane.point)}, {"normal", vec(c.basePlane.normal)}};
    if (c.offset != 0.0) j["offset"] = c.offset;
  }
  if (c.accepted) j["accepted"] = true;
  j["home_direction"] = vec(c.homeDirection);
  if (c.found) {
    Ordered f{{"clearance", c.found->clearance}, {"overlap", c.found->overlap}, {"from_spline", c.found->fromSpline}};
    if (c.type == Constraint::Type::Insert) {
      f["part_radius"] = c.found->partRadius;
      f["partner_radius"] = c.found->partnerRadius;
      if (c.found->fit != Constraint::Found::Fit::Clearance) {
        f["fit"] = std::string(name(c.found->fit));
        f["interference"] = c.found->interference;
        if (!c.found->thread.empty()) f["thread"] = c.found->thread;
      }
      if (c.found->seat != Constraint::Found::Seat::None) {
        f["seat"] = std::string(name(c.found->seat));
        f["seat_radius"] = c.found->seatRadius;
        if (c.found->seat == Constraint::Found::Seat::Countersink)
          f["seat_angle"] = c.found->seatAngle * 180.0 / std::numbers::pi;
      }
    } else if (c.found->keyWidth > 0.0) {
      f["key_width"] = c.found->keyWidth;
    }
    j["found"] = f;
  }
  return j;
}

Ordered settingsJson(const Assembly& loaded, const World& world) {
  const Settings& s = world.settings();
  Ordered materials = Ordered::object();
  for (const auto& [name, m] : loaded.materials) materials[name] = frictionJson(world.materialFriction(name));
  Ordered parts = Ordered::object();
  for (PartId id = 0; id < loaded.parts.size(); ++id) {
    if (const auto f = world.frictionOverride(id)) parts[loaded.parts[id].name] = frictionJson(*f);
  }
  Ordered friction{{"materials", materials}};
  if (!parts.empty()) friction["parts"] = parts;
  return Ordered{{"rate", s.rate},
                 {"gravity_scale", {{"free_flight", s.gravity.freeFlight}, {"slide", s.gravity.slide}, {"rotation", s.gravity.rotation}}},
                 {"rotation_method", std::string(dyn::name(s.rotationMethod))},
                 {"friction", friction}};
}

// A CAD assembly is saved as a scene that refers to its file: the parts stay in the file, the scene holds
// what the user decided (base, constraints, tuning), and the file's hash tells when it changed.
void saveCadScene(const Assembly& loaded, const World& world, const std::filesystem::path& target) {
  const std::filesystem::path toDir = std::filesystem::absolute(target).parent_path();
  const std::filesystem::path cad = std::filesystem::absolute(loaded.cadFile).lexically_normal();
  const std::filesystem::path rel = cad.lexically_relative(toDir);
  Ordered cadJson{{"file", rel.empty() ? cad.generic_string() : rel.generic_string()}, {"hash", loaded.cadHash}};
  if (loaded.base) cadJson["base"] = loaded.parts[*loaded.base].name;
  if (loaded.cadUp != "auto") cadJson["up"] = loaded.cadUp;
  if (!loaded.cadSplit.empty()) cadJson["units_apart"] = std::vector<std::string>(loaded.cadSplit.begin(), loaded.cadSplit.end());
  if (!loaded.cadJoin.empty()) cadJson["units_joined"] = std::vector<std::string>(loaded.cadJoin.begin(), loaded.cadJoin.end());
  // A mesh file declares no unit: the one assumed when it was opened goes with it.
  if (!loaded.parts.empty() && loaded.parts.front().massSource == MassSource::Mesh) cadJson["units"] = std::string(name(loaded.units));
  Ordered constraints = Ordered::array();
  for (const Constraint& c : loaded.constraints) constraints.push_back(constraintJson(loaded, c));
  const Ordered json{{"format", "vaw-scene"},          {"version", 3},
                     {"name", loaded.name},            {"units", "m"},
                     {"cad", cadJson},                 {"constraints", constraints},
                     {"settings", settingsJson(loaded, world)}};
  writeFileAtomically(target, json.dump(2) + "\n");
}

}  // namespace

void saveScene(const Assembly& loaded, const World& world, const std::filesystem::path& target) {
  if (!loaded.cadFile.empty()) {
    saveCadScene(loaded, world, target);
    return;
  }
  const std::string source = loaded.source.string();
  std::ifstream in(loaded.source, std::ios::binary);
  if (!in) fail(source, "", "the scene file the assembly was loaded from, readable (it is saved from it)");
  std::stringstream text;
  text << in.rdbuf();
  Ordered json;
  try {
    json = Ordered::parse(text.str());
  } catch (const std::exception& e) {
    fail(source, "", "the scene file as it was loaded (it changed on disk since)", e.what());
  }
  const std::filesystem::path fromDir = std::filesystem::absolute(loaded.source).parent_path();
  const std::filesystem::path toDir = std::filesystem::absolute(target).parent_path();
  if (json.contains("parts")) rebaseNodes(json["parts"], fromDir, toDir);
  if (json.contains("environment")) rebaseNodes(json["environment"], fromDir, toDir);
  json["version"] = 2;

  json["settings"] = settingsJson(loaded, world);

  // The previous file stays whole until the new one is complete on disk.
  writeFileAtomically(target, json.dump(2) + "\n");
}

}  // namespace vaw::sim
