#pragma once
// Uploads a core view::MeshBuffer (flat-shaded, position and normal per vertex) as a Qt3D geometry
// renderer. The vertex layout and normals come from the core, so the headset renderer draws the same.
#include <Qt3DRender/QGeometryRenderer>

#include "vaw/view/frame.hpp"

namespace vaw::ui {

Qt3DRender::QGeometryRenderer* makeRenderer(const vaw::view::MeshBuffer& mesh, Qt3DCore::QNode* parent);

}  // namespace vaw::ui
