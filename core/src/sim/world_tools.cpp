// The hoist (ONTOOL): a hook on a vertical line that takes a tool-lifted part within its reach, carries it
// up, down and round the vertical, and lets it go onto its mate, at its final pose, or where it is.
#include <algorithm>

#include "world_impl.hpp"

namespace vaw::sim {

using detail::fmt;
using interact::Event;

Eigen::Isometry3d World::Impl::hoistFrame(const HoistInput& hi) const {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = Eigen::AngleAxisd(hi.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector2d xy = hoistTool ? hoistTool->position : Eigen::Vector2d::Zero();
  const double z = hoistTool ? std::clamp(hi.height, hoistTool->lowest, hoistTool->highest) : hi.height;
  f.translation() = Eigen::Vector3d(xy.x(), xy.y(), z);
  return f;
}

void World::Impl::hoist(const HoistInput& hi) {
  if (!hoistTool) return;
  hook = hoistFrame(hi);
  if (prevHoist && !hi.engaged && onHoist) {
    const PartId id = *onHoist;
    onHoist.reset();
    letGo(id, true, interact::Hands::None);
  }
  if (hi.engaged && !prevHoist && !onHoist) {
    flush();
    if (const auto target = nearest(hook->translation(), hoistTool->reach, true)) {
      if (fireEvent(*target, Event::ToolAttach, interact::Hands::None, fmt("hoist at z=%.4f m", hook->translation().z()))) {
        parts[*target].holder = Holder::Hoist;
        parts[*target].model = Model::Kinematic;
        parts[*target].constraint.reset();
        models[*target].offset = hook->inverse() * parts[*target].pose;
        onHoist = target;
      }
    }
  }
  prevHoist = hi.engaged;
}

}  // namespace vaw::sim
