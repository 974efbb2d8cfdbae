#include "sim/io/gltf.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "sim/geometry/mesh.hpp"

namespace brisance::io {

namespace {

using nlohmann::json;

// Constants of the glTF 2.0 specification.
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF", little-endian
constexpr std::uint32_t kGlbVersion = 2;
constexpr std::uint32_t kChunkTypeJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkTypeBin = 0x004E4942;   // "BIN\0"
constexpr std::size_t kGlbHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;
constexpr int kComponentUnsignedShort = 5123;
constexpr int kComponentUnsignedInt = 5125;
constexpr int kComponentFloat = 5126;
constexpr int kTargetArrayBuffer = 34962;
constexpr int kTargetElementArrayBuffer = 34963;
constexpr int kModeTriangles = 4;
// An UNSIGNED_SHORT index may not be 65535 (the primitive restart value), so 16-bit indices hold
// at most 65535 vertices, numbered 0..65534.
constexpr std::size_t kMaxVerticesShortIndices = 65535;

// The look of each kind of material (docs/pipelines.md "What result.glb holds"): chosen to read
// well in a viewer, not measured. Glass blends (alpha), seen from both sides; the crack faces of
// a broken pane's fragments are their own, frostier material.
struct Look {
  const char* name;
  std::array<double, 4> colour;  // linear RGBA
  double metallic;
  double roughness;
  bool blend;  // alphaMode BLEND and doubleSided
};
enum class LookKind { plain, glass, crack_faces, brick, masonry, metal, wood, kCount };
constexpr std::array<Look, static_cast<std::size_t>(LookKind::kCount)> kLooks{{
    {"default", {0.72, 0.72, 0.70, 1.0}, 0.0, 0.8, false},  // bare concrete or painted metal
    {"glass", {0.62, 0.80, 0.86, 0.30}, 0.0, 0.05, true},
    {"glass crack faces", {0.90, 0.96, 0.98, 0.80}, 0.0, 0.35, true},
    {"brick", {0.55, 0.22, 0.14, 1.0}, 0.0, 0.9, false},
    {"masonry", {0.60, 0.59, 0.56, 1.0}, 0.0, 0.95, false},
    {"metal", {0.62, 0.63, 0.65, 1.0}, 1.0, 0.35, false},
    {"wood", {0.45, 0.28, 0.14, 1.0}, 0.0, 0.7, false},
}};

// The look of a body made of `material` (the materials table's name, or "").
LookKind look_of(std::string_view material) {
  if (material.find("glass") != std::string_view::npos) return LookKind::glass;
  if (material == "brick") return LookKind::brick;
  if (material == "concrete" || material == "stone" || material == "granite")
    return LookKind::masonry;
  if (material == "steel" || material == "aluminium") return LookKind::metal;
  if (material == "wood") return LookKind::wood;
  return LookKind::plain;
}

void append_u16(std::vector<std::uint8_t>& bytes, std::uint16_t value) {
  bytes.push_back(static_cast<std::uint8_t>(value & 0xFFu));
  bytes.push_back(static_cast<std::uint8_t>(value >> 8));
}

void append_u32(std::vector<std::uint8_t>& bytes, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8)
    bytes.push_back(static_cast<std::uint8_t>((value >> shift) & 0xFFu));
}

void append_f32(std::vector<std::uint8_t>& bytes, float value) {
  append_u32(bytes, std::bit_cast<std::uint32_t>(value));
}

void pad_to_4(std::vector<std::uint8_t>& bytes, std::uint8_t fill) {
  while (bytes.size() % 4 != 0)
    bytes.push_back(fill);
}

// The buffer views of the file, one per kind of data; each is built on its own and placed in
// the buffer at the end, 4-byte aligned, and left out if empty (a bufferView may not be empty).
// Vertex attributes of all meshes share one view per attribute, so that view needs a byteStride
// (required when several vertex accessors use one view); index and animation views must not
// have one.
enum class View : std::size_t {
  kPositions,
  kNormals,
  kIndices16,
  kIndices32,
  kTimes,
  kTranslations,
  kRotations,
  kCount
};

struct ViewData {
  std::vector<std::uint8_t> bytes;
  std::optional<int> target;       // ARRAY_BUFFER / ELEMENT_ARRAY_BUFFER; none for animation
  std::optional<int> byte_stride;  // only for vertex attributes
};

struct Accessor {
  View view = View::kPositions;
  std::size_t byte_offset = 0;  // within the view
  int component_type = kComponentFloat;
  std::size_t count = 0;
  const char* type = "SCALAR";
  json min;  // null when not written
  json max;
};

// The world position of the point `pivot` (shape frame) of a body at `pose`.
std::array<double, 3> pivot_position(const engine::Pose& pose, const geometry::Vec3& pivot) {
  const Eigen::Quaterniond q(pose.orientation[3], pose.orientation[0], pose.orientation[1],
                             pose.orientation[2]);
  const geometry::Vec3 rotated =
      (q.norm() > 0.0 ? q.normalized() : Eigen::Quaterniond::Identity()) * pivot;
  return {pose.position[0] + rotated.x(), pose.position[1] + rotated.y(),
          pose.position[2] + rotated.z()};
}

// Where a body's node sits in its shape frame: the centre of mass of its (closed) mesh, so that a
// compositor's pivot, motion blur and rotation are about the piece itself (a fragment's shape
// frame is its pane's centre). The centroid of the signed tetrahedra from the origin to each
// triangle (divergence theorem); a mesh without volume (open, flat) takes the mean of its
// vertices. Any mesh is accepted: the writer does not require closed meshes.
geometry::Vec3 node_pivot(const geometry::TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return geometry::Vec3::Zero();
  double six_volume = 0.0;
  geometry::Vec3 weighted = geometry::Vec3::Zero();
  double extent = 0.0;
  for (const auto& triangle : mesh.triangles) {
    const geometry::Vec3& a = mesh.vertices[triangle[0]];
    const geometry::Vec3& b = mesh.vertices[triangle[1]];
    const geometry::Vec3& c = mesh.vertices[triangle[2]];
    const double v = a.dot(b.cross(c));
    six_volume += v;
    weighted += v * (a + b + c);
    extent = std::max(
        {extent, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff()});
  }
  if (six_volume > 1e-12 * extent * extent * extent && weighted.allFinite())
    return weighted / (4.0 * six_volume);
  geometry::Vec3 sum = geometry::Vec3::Zero();
  for (const geometry::Vec3& vertex : mesh.vertices)
    sum += vertex;
  return sum / static_cast<double>(mesh.vertices.size());
}

class GlbBuilder {
 public:
  GlbBuilder() {
    view(View::kPositions) = {{}, kTargetArrayBuffer, 12};
    view(View::kNormals) = {{}, kTargetArrayBuffer, 12};
    view(View::kIndices16) = {{}, kTargetElementArrayBuffer, std::nullopt};
    view(View::kIndices32) = {{}, kTargetElementArrayBuffer, std::nullopt};
  }

  // The mesh of one body, flat shaded: every triangle gets its own three vertices carrying the
  // exact face normal (bodies are rigid polyhedra, so shared smoothed normals would be wrong).
  // Returns the glTF mesh index, or nullopt for a body without triangles.
  std::optional<std::size_t> add_mesh(const engine::BodyInfo& body, const geometry::Vec3& pivot);

  // The "blast" animation: a translation and a rotation channel per animated body, LINEAR,
  // sampled at the frame times. Needs at least one animated body and two frames.
  // `pivots[b]`: body b's node origin in its shape frame (its centre of mass).
  void add_animation(const FrameSet& frames, const std::vector<geometry::Vec3>& pivots);

  std::vector<std::uint8_t> finish(json nodes, std::size_t node_count);

 private:
  ViewData& view(View v) { return views_[static_cast<std::size_t>(v)]; }

  std::size_t add_accessor(Accessor accessor) {
    accessors_.push_back(std::move(accessor));
    return accessors_.size() - 1;
  }

  std::size_t add_times_accessor(const std::vector<double>& times_s);
  // One primitive of the triangles `which` of `mesh` (flat shaded, about `pivot`) in `look`.
  json add_primitive(const geometry::TriangleMesh& mesh, const std::vector<std::size_t>& which,
                     const geometry::Vec3& pivot, LookKind look);
  // The glTF material index of `look`: materials are written as the meshes first use them.
  std::size_t material(LookKind look);

  std::array<ViewData, static_cast<std::size_t>(View::kCount)> views_;
  std::vector<Accessor> accessors_;
  std::array<std::optional<std::size_t>, static_cast<std::size_t>(LookKind::kCount)> material_of_;
  json materials_ = json::array();
  json meshes_ = json::array();
  json animations_ = json::array();
};

std::size_t GlbBuilder::material(LookKind look) {
  std::optional<std::size_t>& index = material_of_[static_cast<std::size_t>(look)];
  if (!index) {
    const Look& l = kLooks[static_cast<std::size_t>(look)];
    json entry = {{"name", l.name},
                  {"pbrMetallicRoughness",
                   {{"baseColorFactor", l.colour},
                    {"metallicFactor", l.metallic},
                    {"roughnessFactor", l.roughness}}}};
    if (l.blend) {
      entry["alphaMode"] = "BLEND";
      entry["doubleSided"] = true;
    }
    materials_.push_back(std::move(entry));
    index = materials_.size() - 1;
  }
  return *index;
}

std::optional<std::size_t> GlbBuilder::add_mesh(const engine::BodyInfo& body,
                                                const geometry::Vec3& pivot) {
  const geometry::TriangleMesh& mesh = body.mesh;
  if (mesh.triangles.empty()) return std::nullopt;
  const LookKind look = look_of(body.material);
  json primitives = json::array();
  if (body.fragment && look == LookKind::glass) {
    // A fragment is a prism of the pane's thickness along its shape z: the triangles facing
    // along z are the pane's faces, the others its side walls, cracks (or the pane's edge).
    std::vector<std::size_t> faces, walls;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& triangle = mesh.triangles[t];
      const geometry::Vec3 normal =
          (mesh.vertices[triangle[1]] - mesh.vertices[triangle[0]])
              .cross(mesh.vertices[triangle[2]] - mesh.vertices[triangle[0]]);
      (std::abs(normal.z()) >= 0.5 * normal.norm() ? faces : walls).push_back(t);
    }
    if (!faces.empty()) primitives.push_back(add_primitive(mesh, faces, pivot, LookKind::glass));
    if (!walls.empty())
      primitives.push_back(add_primitive(mesh, walls, pivot, LookKind::crack_faces));
  } else {
    std::vector<std::size_t> all(mesh.triangles.size());
    for (std::size_t t = 0; t < all.size(); ++t)
      all[t] = t;
    primitives.push_back(add_primitive(mesh, all, pivot, look));
  }
  meshes_.push_back({{"name", body.name}, {"primitives", std::move(primitives)}});
  return meshes_.size() - 1;
}

json GlbBuilder::add_primitive(const geometry::TriangleMesh& mesh,
                               const std::vector<std::size_t>& which, const geometry::Vec3& pivot,
                               LookKind look) {
  const std::size_t vertex_count = 3 * which.size();
  std::vector<std::uint8_t>& positions = view(View::kPositions).bytes;
  std::vector<std::uint8_t>& normals = view(View::kNormals).bytes;
  const std::size_t position_offset = positions.size();
  const std::size_t normal_offset = normals.size();
  std::array<float, 3> min_f;
  std::array<float, 3> max_f;
  min_f.fill(std::numeric_limits<float>::infinity());
  max_f.fill(-std::numeric_limits<float>::infinity());
  for (const std::size_t t : which) {
    const auto& triangle = mesh.triangles[t];
    assert(triangle[0] < mesh.vertices.size() && triangle[1] < mesh.vertices.size() &&
           triangle[2] < mesh.vertices.size());
    const geometry::Vec3& a = mesh.vertices[triangle[0]];
    const geometry::Vec3& b = mesh.vertices[triangle[1]];
    const geometry::Vec3& c = mesh.vertices[triangle[2]];
    geometry::Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    // A closed mesh has no zero-area triangle; should a sliver still round to one, any unit
    // normal keeps the file valid (a NORMAL must be unit length) and shades an invisible face.
    normal = (length > 0.0 && std::isfinite(length)) ? geometry::Vec3(normal / length)
                                                     : geometry::Vec3::UnitY();
    for (const geometry::Vec3* vertex : {&a, &b, &c}) {
      for (int axis = 0; axis < 3; ++axis) {
        const float coordinate = static_cast<float>((*vertex)[axis] - pivot[axis]);
        min_f[axis] = std::min(min_f[axis], coordinate);
        max_f[axis] = std::max(max_f[axis], coordinate);
        append_f32(positions, coordinate);
        append_f32(normals, static_cast<float>(normal[axis]));
      }
    }
  }

  // The min/max of POSITION are those of the stored floats, which the validator checks exactly.
  const std::size_t position_accessor = add_accessor(
      {View::kPositions, position_offset, kComponentFloat, vertex_count, "VEC3",
       json::array({min_f[0], min_f[1], min_f[2]}), json::array({max_f[0], max_f[1], max_f[2]})});
  const std::size_t normal_accessor =
      add_accessor({View::kNormals, normal_offset, kComponentFloat, vertex_count, "VEC3", {}, {}});

  // Flat shading leaves each vertex used once, so the indices are 0..n-1; 16 bits where they fit.
  std::size_t index_accessor = 0;
  if (vertex_count <= kMaxVerticesShortIndices) {
    std::vector<std::uint8_t>& indices = view(View::kIndices16).bytes;
    const std::size_t offset = indices.size();
    for (std::size_t i = 0; i < vertex_count; ++i)
      append_u16(indices, static_cast<std::uint16_t>(i));
    index_accessor = add_accessor(
        {View::kIndices16, offset, kComponentUnsignedShort, vertex_count, "SCALAR", {}, {}});
  } else {
    std::vector<std::uint8_t>& indices = view(View::kIndices32).bytes;
    const std::size_t offset = indices.size();
    for (std::size_t i = 0; i < vertex_count; ++i)
      append_u32(indices, static_cast<std::uint32_t>(i));
    index_accessor = add_accessor(
        {View::kIndices32, offset, kComponentUnsignedInt, vertex_count, "SCALAR", {}, {}});
  }

  return {{"attributes", {{"POSITION", position_accessor}, {"NORMAL", normal_accessor}}},
          {"indices", index_accessor},
          {"material", material(look)},
          {"mode", kModeTriangles}};
}

// The sampler input: frame times as floats, strictly increasing as the spec requires. Should
// float rounding merge two distinct frame times (only for very long runs at a high frame rate),
// the later one moves up by one float step, an error far below a frame interval.
std::size_t GlbBuilder::add_times_accessor(const std::vector<double>& times_s) {
  std::vector<std::uint8_t>& bytes = view(View::kTimes).bytes;
  assert(bytes.empty());
  float previous = -std::numeric_limits<float>::infinity();
  float first = 0.0f;
  for (std::size_t f = 0; f < times_s.size(); ++f) {
    assert(f == 0 || times_s[f] > times_s[f - 1]);
    float time = static_cast<float>(times_s[f]);
    if (!(time > previous)) time = std::nextafter(previous, std::numeric_limits<float>::infinity());
    if (f == 0) first = time;
    append_f32(bytes, time);
    previous = time;
  }
  return add_accessor({View::kTimes, 0, kComponentFloat, times_s.size(), "SCALAR",
                       json::array({first}), json::array({previous})});
}

void GlbBuilder::add_animation(const FrameSet& frames, const std::vector<geometry::Vec3>& pivots) {
  const std::size_t frame_count = frames.frame_count();
  assert(!frames.bodies.empty() && frame_count >= 2);
  const std::size_t times_accessor = add_times_accessor(frames.times_s);

  std::vector<std::uint8_t>& translations = view(View::kTranslations).bytes;
  std::vector<std::uint8_t>& rotations = view(View::kRotations).bytes;
  json samplers = json::array();
  json channels = json::array();
  for (std::size_t k = 0; k < frames.bodies.size(); ++k) {
    const std::size_t translation_accessor = add_accessor(
        {View::kTranslations, translations.size(), kComponentFloat, frame_count, "VEC3", {}, {}});
    const std::size_t rotation_accessor = add_accessor(
        {View::kRotations, rotations.size(), kComponentFloat, frame_count, "VEC4", {}, {}});
    const geometry::Vec3& pivot = pivots[frames.bodies[k]];
    std::array<double, 4> previous{0.0, 0.0, 0.0, 1.0};
    for (std::size_t f = 0; f < frame_count; ++f) {
      const engine::Pose& pose = frames.pose(f, k);
      for (const double coordinate : pivot_position(pose, pivot))
        append_f32(translations, static_cast<float>(coordinate));
      // q and -q are the same rotation, but LINEAR (slerp) interpolation between samples of
      // opposite sign turns the long way round: keep each sample in the previous one's half.
      std::array<double, 4> q = pose.orientation;
      const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      assert(norm > 0.0);
      double dot = 0.0;
      for (int i = 0; i < 4; ++i) {
        q[i] /= norm;
        dot += q[i] * previous[i];
      }
      if (f > 0 && dot < 0.0)
        for (double& component : q)
          component = -component;
      for (const double component : q)
        append_f32(rotations, static_cast<float>(component));
      previous = q;
    }
    const std::uint32_t node = frames.bodies[k];
    samplers.push_back(
        {{"input", times_accessor}, {"output", translation_accessor}, {"interpolation", "LINEAR"}});
    channels.push_back(
        {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", "translation"}}}});
    samplers.push_back(
        {{"input", times_accessor}, {"output", rotation_accessor}, {"interpolation", "LINEAR"}});
    channels.push_back(
        {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", "rotation"}}}});
  }
  animations_.push_back(
      {{"name", "blast"}, {"samplers", std::move(samplers)}, {"channels", std::move(channels)}});
}

// Lays the views out in one buffer, writes the JSON and packs both chunks into the GLB.
std::vector<std::uint8_t> GlbBuilder::finish(json nodes, std::size_t node_count) {
  std::vector<std::uint8_t> buffer;
  std::array<std::optional<std::size_t>, static_cast<std::size_t>(View::kCount)> view_index;
  std::array<std::size_t, static_cast<std::size_t>(View::kCount)> view_offset{};
  json buffer_views = json::array();
  for (std::size_t v = 0; v < views_.size(); ++v) {
    const ViewData& data = views_[v];
    if (data.bytes.empty()) continue;
    assert(buffer.size() % 4 == 0);
    json buffer_view = {
        {"buffer", 0}, {"byteOffset", buffer.size()}, {"byteLength", data.bytes.size()}};
    if (data.byte_stride) buffer_view["byteStride"] = *data.byte_stride;
    if (data.target) buffer_view["target"] = *data.target;
    view_index[v] = buffer_views.size();
    view_offset[v] = buffer.size();
    buffer_views.push_back(std::move(buffer_view));
    buffer.insert(buffer.end(), data.bytes.begin(), data.bytes.end());
    pad_to_4(buffer, 0);
  }

  json accessors = json::array();
  for (const Accessor& accessor : accessors_) {
    const auto v = static_cast<std::size_t>(accessor.view);
    assert(view_index[v]);
    json entry = {{"bufferView", *view_index[v]},
                  {"byteOffset", accessor.byte_offset},
                  {"componentType", accessor.component_type},
                  {"count", accessor.count},
                  {"type", accessor.type}};
    if (!accessor.min.is_null()) entry["min"] = accessor.min;
    if (!accessor.max.is_null()) entry["max"] = accessor.max;
    accessors.push_back(std::move(entry));
  }

  // Every top-level array of glTF needs at least one element, so empty ones are left out; an
  // empty scene is a scene without "nodes".
  json scene = json::object();
  if (node_count > 0) {
    json scene_nodes = json::array();
    for (std::size_t i = 0; i < node_count; ++i)
      scene_nodes.push_back(i);
    scene["nodes"] = std::move(scene_nodes);
  }
  json gltf = {{"asset", {{"version", "2.0"}, {"generator", "Brisance"}}},
               {"scene", 0},
               {"scenes", json::array({std::move(scene)})}};
  if (node_count > 0) gltf["nodes"] = std::move(nodes);
  if (!meshes_.empty()) {
    gltf["meshes"] = std::move(meshes_);
    gltf["materials"] = std::move(materials_);
  }
  if (!accessors.empty()) gltf["accessors"] = std::move(accessors);
  if (!buffer.empty()) {
    gltf["bufferViews"] = std::move(buffer_views);
    gltf["buffers"] = json::array({{{"byteLength", buffer.size()}}});
  }
  if (!animations_.empty()) gltf["animations"] = std::move(animations_);

  // GLB: a 12-byte header, the JSON chunk padded with spaces, the BIN chunk padded with zeros
  // (the buffer is already a multiple of 4 bytes, so its byteLength is the chunk's length).
  std::string text = gltf.dump();
  while (text.size() % 4 != 0)
    text.push_back(' ');
  const std::size_t total = kGlbHeaderBytes + kChunkHeaderBytes + text.size() +
                            (buffer.empty() ? 0 : kChunkHeaderBytes + buffer.size());
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("result_to_glb: the result needs " + std::to_string(total) +
                            " bytes, more than the 4 GiB a .glb file can hold; write fewer "
                            "frames or bodies");
  std::vector<std::uint8_t> glb;
  glb.reserve(total);
  append_u32(glb, kGlbMagic);
  append_u32(glb, kGlbVersion);
  append_u32(glb, static_cast<std::uint32_t>(total));
  append_u32(glb, static_cast<std::uint32_t>(text.size()));
  append_u32(glb, kChunkTypeJson);
  glb.insert(glb.end(), text.begin(), text.end());
  if (!buffer.empty()) {
    append_u32(glb, static_cast<std::uint32_t>(buffer.size()));
    append_u32(glb, kChunkTypeBin);
    glb.insert(glb.end(), buffer.begin(), buffer.end());
  }
  assert(glb.size() == total);
  return glb;
}

// A unit quaternion [x, y, z, w] for a node; the identity if the input has no direction.
std::array<double, 4> normalized(const std::array<double, 4>& q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(norm > 0.0) || !std::isfinite(norm)) return {0.0, 0.0, 0.0, 1.0};
  return {q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm};
}

}  // namespace

std::vector<std::uint8_t> to_glb(std::span<const engine::BodyInfo> bodies, const FrameSet& frames) {
  assert(frames.poses.size() == frames.frame_count() * frames.bodies.size());
#ifndef NDEBUG
  {
    // Two channels on one node and path would be invalid glTF.
    std::vector<bool> seen(bodies.size(), false);
    for (const std::uint32_t index : frames.bodies) {
      assert(index < bodies.size() && !seen[index]);
      seen[index] = true;
    }
  }
#endif

  GlbBuilder builder;
  // One node per body, node i for body i, placed at the body's initial pose with its origin at
  // the body's centre of mass (the mesh is shifted to match).
  json nodes = json::array();
  std::vector<geometry::Vec3> pivots;
  pivots.reserve(bodies.size());
  for (const engine::BodyInfo& body : bodies) {
    pivots.push_back(node_pivot(body.mesh));
    json node = {{"name", body.name},
                 {"translation", pivot_position(body.initial_pose, pivots.back())},
                 {"rotation", normalized(body.initial_pose.orientation)}};
    if (const std::optional<std::size_t> mesh = builder.add_mesh(body, pivots.back()))
      node["mesh"] = *mesh;
    nodes.push_back(std::move(node));
  }
  if (!frames.bodies.empty() && frames.frame_count() >= 2) builder.add_animation(frames, pivots);
  return builder.finish(std::move(nodes), bodies.size());
}

std::vector<std::uint8_t> result_to_glb(const engine::Result& result) {
  return to_glb(result.bodies, frames_of(result));
}

void write_glb(const engine::Result& result, std::ostream& out) {
  const std::vector<std::uint8_t> glb = result_to_glb(result);
  out.write(reinterpret_cast<const char*>(glb.data()), static_cast<std::streamsize>(glb.size()));
}

}  // namespace brisance::io
