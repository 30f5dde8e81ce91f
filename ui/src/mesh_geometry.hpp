#pragma once
// Turns a vaw::TriMesh into a Qt3D geometry renderer, synchronously (QMesh loads asynchronously).
// Flat shading: every triangle gets its own three vertices carrying the face normal.
#include <Qt3DRender/QGeometryRenderer>

#include "vaw/mesh.hpp"

namespace vaw::ui {

Qt3DRender::QGeometryRenderer* makeFlatShadedRenderer(const vaw::TriMesh& mesh, Qt3DCore::QNode* parent);

}  // namespace vaw::ui
