#include "mesh_geometry.hpp"

#include <Qt3DCore/QAttribute>
#include <Qt3DCore/QBuffer>
#include <Qt3DCore/QGeometry>
#include <QByteArray>

namespace vaw::ui {

Qt3DRender::QGeometryRenderer* makeRenderer(const vaw::view::MeshBuffer& mesh, Qt3DCore::QNode* parent) {
  using Qt3DCore::QAttribute;
  constexpr auto kStride = static_cast<uint>(vaw::view::kFloatsPerVertex * sizeof(float));
  const auto count = static_cast<uint>(mesh.vertexCount);
  const QByteArray bytes(reinterpret_cast<const char*>(mesh.vertices.data()),
                         static_cast<qsizetype>(mesh.vertices.size() * sizeof(float)));

  auto* renderer = new Qt3DRender::QGeometryRenderer(parent);
  auto* geometry = new Qt3DCore::QGeometry(renderer);
  auto* buffer = new Qt3DCore::QBuffer(geometry);
  buffer->setData(bytes);
  const auto attribute = [&](const QString& name, uint offset) {
    auto* a = new QAttribute(geometry);
    a->setName(name);
    a->setAttributeType(QAttribute::VertexAttribute);
    a->setVertexBaseType(QAttribute::Float);
    a->setVertexSize(3);
    a->setBuffer(buffer);
    a->setByteOffset(offset);
    a->setByteStride(kStride);
    a->setCount(count);
    geometry->addAttribute(a);
    return a;
  };
  QAttribute* position = attribute(QAttribute::defaultPositionAttributeName(), 0);
  attribute(QAttribute::defaultNormalAttributeName(), static_cast<uint>(3 * sizeof(float)));
  geometry->setBoundingVolumePositionAttribute(position);
  renderer->setGeometry(geometry);
  renderer->setPrimitiveType(Qt3DRender::QGeometryRenderer::Triangles);
  renderer->setVertexCount(static_cast<int>(count));
  return renderer;
}

}  // namespace vaw::ui
