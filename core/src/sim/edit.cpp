#include "vaw/sim/edit.hpp"

#include <cmath>
#include <cstdio>

#include "vaw/dynamics/hinge.hpp"

namespace vaw::sim {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string frictionText(const FrictionValues& f) {
  return "static " + num(f.staticFriction) + ", kinetic " + num(f.kineticFriction) + ", rotational " +
         num(f.rotationalFriction) + " N m s";
}

}  // namespace

std::string validateFriction(const FrictionValues& f) {
  const auto bad = [](double v) { return !std::isfinite(v); };
  if (bad(f.staticFriction) || bad(f.kineticFriction) || bad(f.rotationalFriction))
    return "friction coefficients must be numbers (found static " + num(f.staticFriction) + ", kinetic " +
           num(f.kineticFriction) + ", rotational " + num(f.rotationalFriction) + ")";
  if (f.staticFriction < 0.0) return "static friction must not be negative (found " + num(f.staticFriction) + ")";
  if (f.kineticFriction < 0.0) return "kinetic friction must not be negative (found " + num(f.kineticFriction) + ")";
  if (f.rotationalFriction < 0.0)
    return "rotational friction must not be negative (found " + num(f.rotationalFriction) + " N m s)";
  if (f.kineticFriction > f.staticFriction)
    return "kinetic friction must not exceed static friction (found kinetic " + num(f.kineticFriction) + " > static " +
           num(f.staticFriction) + ")";
  return {};
}

bool rotationSupports(dyn::Method m) { return dyn::supports(dyn::Hinge::kMethods, m); }

std::string describe(const Edit& e, const Assembly& assembly) {
  if (const auto* g = std::get_if<GravityEdit>(&e))
    return "gravity scales: free flight " + num(g->scales.freeFlight) + ", slide " + num(g->scales.slide) +
           ", rotation " + num(g->scales.rotation);
  if (const auto* m = std::get_if<MaterialFrictionEdit>(&e))
    return "friction of " + m->material + ": " + frictionText(m->friction);
  if (const auto* p = std::get_if<PartFrictionEdit>(&e)) {
    const std::string who = p->part < assembly.parts.size() ? assembly.parts[p->part].name : "part " + std::to_string(p->part);
    return p->friction ? "friction of " + who + " (override): " + frictionText(*p->friction)
                       : "friction of " + who + ": its material's";
  }
  if (const auto* m = std::get_if<MethodEdit>(&e)) return "rotation method: " + std::string(dyn::name(m->rotation));
  if (const auto* r = std::get_if<RateEdit>(&e)) return "step rate: " + num(r->rate) + " Hz";
  return "?";
}

std::string validate(const Edit& e, const Assembly& assembly) {
  if (const auto* g = std::get_if<GravityEdit>(&e)) {
    const std::pair<const char*, double> scales[] = {
        {"free flight", g->scales.freeFlight}, {"slide", g->scales.slide}, {"rotation", g->scales.rotation}};
    for (const auto& [what, v] : scales)
      if (!(v >= 0.0 && v <= kMaxGravityScale))
        return std::string("the ") + what + " gravity scale must be between 0 and " + num(kMaxGravityScale) +
               " (found " + num(v) + ")";
    return {};
  }
  if (const auto* m = std::get_if<MaterialFrictionEdit>(&e)) {
    if (!assembly.materials.contains(m->material)) return "no material named \"" + m->material + "\" in this scene";
    return validateFriction(m->friction);
  }
  if (const auto* p = std::get_if<PartFrictionEdit>(&e)) {
    if (p->part >= assembly.parts.size()) return "no part " + std::to_string(p->part) + " in this scene";
    return p->friction ? validateFriction(*p->friction) : std::string();
  }
  if (const auto* m = std::get_if<MethodEdit>(&e)) {
    if (!rotationSupports(m->rotation))
      return std::string("rotation about an axis cannot use ") + std::string(dyn::name(m->rotation)) +
             ": its torque depends on the angle, so there is no constant-acceleration closed form";
    return {};
  }
  if (const auto* r = std::get_if<RateEdit>(&e)) {
    if (!(r->rate >= kMinRate && r->rate <= kMaxRate))
      return "the step rate must be between " + num(kMinRate) + " and " + num(kMaxRate) + " Hz (found " + num(r->rate) + ")";
    return {};
  }
  return "unknown edit";
}

}  // namespace vaw::sim
