#include "mesh_geometry.hpp"

#include <Qt3DCore/QAttribute>
#include <Qt3DCore/QBuffer>
#include <Qt3DCore/QGeometry>
#include <QByteArray>
#include <cstring>

namespace vaw::ui {

Qt3DRender::QGeometryRenderer* makeFlatShadedRenderer(const vaw::TriMesh& mesh, Qt3DCore::QNode* parent) {
  using Qt3DCore::QAttribute;
  constexpr int kFloatsPerVertex = 6;  // position xyz, normal xyz
  constexpr auto kStride = static_cast<uint>(kFloatsPerVertex * sizeof(float));

  const auto vertexCount = static_cast<qsizetype>(mesh.triangles.size() * 3);
  QByteArray bytes(vertexCount * kFloatsPerVertex * static_cast<qsizetype>(sizeof(float)), Qt::Uninitialized);
  std::vector<float> data;
  data.reserve(static_cast<std::size_t>(vertexCount) * kFloatsPerVertex);
  const auto vertexCountInMesh = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= vertexCountInMesh) {
      data.insert(data.end(), 3 * kFloatsPerVertex, 0.0f);  // the core rejects these; draw nothing
      continue;
    }
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t.x())];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t.y())];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t.z())];
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    n = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3f nf = n.cast<float>();
    for (const Eigen::Vector3d* p : {&a, &b, &c}) {
      const Eigen::Vector3f pf = p->cast<float>();
      data.insert(data.end(), {pf.x(), pf.y(), pf.z(), nf.x(), nf.y(), nf.z()});
    }
  }
  std::memcpy(bytes.data(), data.data(), data.size() * sizeof(float));

  auto* renderer = new Qt3DRender::QGeometryRenderer(parent);
  auto* geometry = new Qt3DCore::QGeometry(renderer);
  auto* buffer = new Qt3DCore::QBuffer(geometry);
  buffer->setData(bytes);

  auto* position = new QAttribute(geometry);
  position->setName(QAttribute::defaultPositionAttributeName());
  position->setAttributeType(QAttribute::VertexAttribute);
  position->setVertexBaseType(QAttribute::Float);
  position->setVertexSize(3);
  position->setBuffer(buffer);
  position->setByteOffset(0);
  position->setByteStride(kStride);
  position->setCount(static_cast<uint>(vertexCount));
  geometry->addAttribute(position);

  auto* normal = new QAttribute(geometry);
  normal->setName(QAttribute::defaultNormalAttributeName());
  normal->setAttributeType(QAttribute::VertexAttribute);
  normal->setVertexBaseType(QAttribute::Float);
  normal->setVertexSize(3);
  normal->setBuffer(buffer);
  normal->setByteOffset(static_cast<uint>(3 * sizeof(float)));
  normal->setByteStride(kStride);
  normal->setCount(static_cast<uint>(vertexCount));
  geometry->addAttribute(normal);

  geometry->setBoundingVolumePositionAttribute(position);
  renderer->setGeometry(geometry);
  renderer->setPrimitiveType(Qt3DRender::QGeometryRenderer::Triangles);
  renderer->setVertexCount(static_cast<int>(vertexCount));
  return renderer;
}

}  // namespace vaw::ui
