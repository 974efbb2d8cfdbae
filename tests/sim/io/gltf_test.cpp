// Tests of sim/io/gltf: the GLB container, the glTF JSON and the binary data read back
// independently of the writer (glTF 2.0 specification, "GLB File Format Specification").
#include "sim/io/gltf.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace brisance::io {
namespace {

using nlohmann::json;

constexpr std::uint32_t kMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;
constexpr std::uint32_t kBinChunk = 0x004E4942;

std::uint32_t read_u32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i)
    value |= std::uint32_t{bytes.at(at + i)} << (8 * i);
  return value;
}

float read_f32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  return std::bit_cast<float>(read_u32(bytes, at));
}

struct Glb {
  json gltf;
  std::vector<std::uint8_t> bin;  // empty when the file has no BIN chunk
};

// Parses the container, checking every rule of the GLB layout on the way.
::testing::AssertionResult parse_glb(const std::vector<std::uint8_t>& file, Glb& glb) {
  if (file.size() < 20) return ::testing::AssertionFailure() << "too short: " << file.size();
  if (read_u32(file, 0) != kMagic) return ::testing::AssertionFailure() << "bad magic";
  if (read_u32(file, 4) != 2) return ::testing::AssertionFailure() << "version not 2";
  if (read_u32(file, 8) != file.size())
    return ::testing::AssertionFailure()
           << "header length " << read_u32(file, 8) << " != file size " << file.size();
  const std::uint32_t json_length = read_u32(file, 12);
  if (read_u32(file, 16) != kJsonChunk)
    return ::testing::AssertionFailure() << "first chunk is not JSON";
  if (json_length % 4 != 0 || 20 + std::size_t{json_length} > file.size())
    return ::testing::AssertionFailure() << "bad JSON chunk length " << json_length;
  const std::string text(file.begin() + 20, file.begin() + 20 + json_length);
  const std::size_t end_of_json = text.find_last_not_of(' ');
  if (end_of_json == std::string::npos || text[end_of_json] != '}' ||
      text.size() - end_of_json - 1 >= 4)
    return ::testing::AssertionFailure() << "JSON chunk not padded with fewer than 4 spaces";
  glb.gltf = json::parse(text);
  glb.bin.clear();
  std::size_t at = 20 + json_length;
  if (at == file.size()) return ::testing::AssertionSuccess();
  if (at + 8 > file.size()) return ::testing::AssertionFailure() << "truncated BIN chunk header";
  const std::uint32_t bin_length = read_u32(file, at);
  if (read_u32(file, at + 4) != kBinChunk)
    return ::testing::AssertionFailure() << "second chunk is not BIN";
  if (bin_length % 4 != 0 || at + 8 + bin_length != file.size())
    return ::testing::AssertionFailure() << "bad BIN chunk length " << bin_length;
  glb.bin.assign(file.begin() + static_cast<std::ptrdiff_t>(at + 8), file.end());
  return ::testing::AssertionSuccess();
}

Glb parsed(const engine::Result& result) {
  Glb glb;
  EXPECT_TRUE(parse_glb(result_to_glb(result), glb));
  return glb;
}

// Component `c` of element `i` of a float accessor, read through its bufferView.
float accessor_float(const Glb& glb, std::size_t accessor, std::size_t i, std::size_t c) {
  const json& a = glb.gltf["accessors"][accessor];
  const json& view = glb.gltf["bufferViews"][a["bufferView"].get<std::size_t>()];
  EXPECT_EQ(a["componentType"], 5126);
  const std::size_t components = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : 4;
  const std::size_t stride = view.value("byteStride", components * 4);
  return read_f32(glb.bin, view["byteOffset"].get<std::size_t>() +
                               a.value("byteOffset", std::size_t{0}) + i * stride + c * 4);
}

std::uint32_t accessor_index(const Glb& glb, std::size_t accessor, std::size_t i) {
  const json& a = glb.gltf["accessors"][accessor];
  const json& view = glb.gltf["bufferViews"][a["bufferView"].get<std::size_t>()];
  const std::size_t at = view["byteOffset"].get<std::size_t>() + a.value("byteOffset", 0u);
  if (a["componentType"] == 5123) return glb.bin.at(at + 2 * i) | glb.bin.at(at + 2 * i + 1) << 8;
  EXPECT_EQ(a["componentType"], 5125);
  return read_u32(glb.bin, at + 4 * i);
}

// A box of half extents (hx, hy, hz).
geometry::TriangleMesh box(double hx, double hy, double hz) {
  return geometry::make_box(geometry::Vec3(2.0 * hx, 2.0 * hy, 2.0 * hz));
}

// A strip of `count` triangles in the z = 0 plane (the writer needs no closed mesh).
geometry::TriangleMesh strip(std::size_t count) {
  geometry::TriangleMesh mesh;
  for (std::size_t i = 0; i < count + 2; ++i)
    mesh.vertices.emplace_back(0.01 * static_cast<double>(i / 2), i % 2 ? 0.1 : 0.0, 0.0);
  for (std::uint32_t t = 0; t < count; ++t) {
    if (t % 2 == 0)
      mesh.triangles.push_back({t, t + 1, t + 2});
    else
      mesh.triangles.push_back({t + 1, t, t + 2});
  }
  return mesh;
}

std::array<double, 4> about_axis(const std::array<double, 3>& unit_axis, double angle_rad) {
  const double s = std::sin(angle_rad / 2);
  return {unit_axis[0] * s, unit_axis[1] * s, unit_axis[2] * s, std::cos(angle_rad / 2)};
}

// Four bodies, the second and fourth animated (listed as 3, 1), over `frames` frames at 60 Hz.
// Odd frames store the negated quaternion of body 3, as an integrator may, and body 1 turns
// through more than a full turn so its quaternion's w changes sign.
engine::Result synthetic_result(std::size_t frames = 5) {
  engine::Result result;
  const char* names[] = {"ground", "door", "wall", "window"};
  for (std::size_t i = 0; i < 4; ++i) {
    engine::BodyInfo body;
    body.name = names[i];
    body.mass_kg = 1.0;
    body.mesh = box(0.5 + 0.25 * static_cast<double>(i), 1.0, 0.125);
    body.initial_pose.position = {static_cast<double>(i), 1.0, -2.0};
    body.initial_pose.orientation = about_axis({0.0, 0.0, 1.0}, 0.25 * static_cast<double>(i));
    result.bodies.push_back(body);
  }
  result.animated = {3, 1};
  for (std::size_t f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / 60.0;
    result.frame_times_s.push_back(t);
    engine::Pose window;
    window.position = {3.0 + 2.0 * t, 1.0 + t, -2.0 - 0.5 * t};
    window.orientation = about_axis({0.6, 0.0, 0.8}, 0.2 * static_cast<double>(f));
    if (f % 2 == 1)
      for (double& component : window.orientation)
        component = -component;
    engine::Pose door;
    door.position = {1.0, 1.0 - t * t, -2.0};
    door.orientation = about_axis({0.0, 1.0, 0.0}, 1.7 * static_cast<double>(f));
    result.poses.push_back(window);
    result.poses.push_back(door);
  }
  return result;
}

TEST(Glb, ContainerHeaderAndChunksFollowTheSpec) {
  const engine::Result result = synthetic_result();
  const std::vector<std::uint8_t> file = result_to_glb(result);
  Glb glb;
  ASSERT_TRUE(parse_glb(file, glb));
  ASSERT_FALSE(glb.bin.empty());
  ASSERT_EQ(glb.gltf["buffers"].size(), 1u);
  EXPECT_EQ(glb.gltf["buffers"][0]["byteLength"].get<std::size_t>(), glb.bin.size());
  EXPECT_FALSE(glb.gltf["buffers"][0].contains("uri"));
  EXPECT_EQ(glb.gltf["asset"]["version"], "2.0");
  EXPECT_EQ(glb.gltf["asset"]["generator"], "Brisance");

  std::ostringstream out;
  write_glb(result, out);
  EXPECT_EQ(out.str(), std::string(file.begin(), file.end()));
}

TEST(Glb, OneNamedNodePerBodyAtItsInitialPoseAllInSceneZero) {
  const engine::Result result = synthetic_result();
  const Glb glb = parsed(result);
  const json& nodes = glb.gltf["nodes"];
  ASSERT_EQ(nodes.size(), result.bodies.size());
  EXPECT_EQ(glb.gltf["scene"], 0);
  EXPECT_EQ(glb.gltf["scenes"][0]["nodes"], (json{0, 1, 2, 3}));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    SCOPED_TRACE(i);
    const engine::Pose& pose = result.bodies[i].initial_pose;
    EXPECT_EQ(nodes[i]["name"], result.bodies[i].name);
    EXPECT_EQ(nodes[i]["mesh"], i);
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_DOUBLE_EQ(nodes[i]["translation"][c].get<double>(), pose.position[c]);
    for (std::size_t c = 0; c < 4; ++c)
      EXPECT_NEAR(nodes[i]["rotation"][c].get<double>(), pose.orientation[c], 1e-15);
  }
  const json& material = glb.gltf["materials"].at(0);
  EXPECT_TRUE(material["pbrMetallicRoughness"].contains("baseColorFactor"));
}

TEST(Glb, MeshesAreFlatShadedWithExactBoundsAndFaceNormals) {
  const engine::Result result = synthetic_result();
  const Glb glb = parsed(result);
  ASSERT_EQ(glb.gltf["meshes"].size(), result.bodies.size());
  for (std::size_t i = 0; i < result.bodies.size(); ++i) {
    SCOPED_TRACE(i);
    const geometry::TriangleMesh& mesh = result.bodies[i].mesh;
    const json& primitive = glb.gltf["meshes"][i]["primitives"].at(0);
    EXPECT_EQ(primitive["material"], 0);
    const std::size_t position = primitive["attributes"]["POSITION"];
    const std::size_t normal = primitive["attributes"]["NORMAL"];
    const std::size_t indices = primitive["indices"];
    const std::size_t vertex_count = 3 * mesh.triangles.size();
    const json& accessors = glb.gltf["accessors"];
    EXPECT_EQ(accessors[position]["count"], vertex_count);
    EXPECT_EQ(accessors[normal]["count"], vertex_count);
    EXPECT_EQ(accessors[indices]["count"], vertex_count);
    EXPECT_EQ(accessors[indices]["componentType"], 5123);  // 36 vertices fit 16 bits
    const double half_x = 0.5 + 0.25 * static_cast<double>(i);
    EXPECT_EQ(accessors[position]["min"], (json{-half_x, -1.0, -0.125}));
    EXPECT_EQ(accessors[position]["max"], (json{half_x, 1.0, 0.125}));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const geometry::Vec3& a = mesh.vertices[mesh.triangles[t][0]];
      const geometry::Vec3& b = mesh.vertices[mesh.triangles[t][1]];
      const geometry::Vec3& c = mesh.vertices[mesh.triangles[t][2]];
      const geometry::Vec3 face_normal = (b - a).cross(c - a).normalized();
      for (std::size_t corner = 0; corner < 3; ++corner) {
        const std::size_t v = 3 * t + corner;
        EXPECT_EQ(accessor_index(glb, indices, v), v);
        const geometry::Vec3& vertex = mesh.vertices[mesh.triangles[t][corner]];
        for (std::size_t axis = 0; axis < 3; ++axis) {
          EXPECT_EQ(accessor_float(glb, position, v, axis), static_cast<float>(vertex[axis]));
          EXPECT_NEAR(accessor_float(glb, normal, v, axis), face_normal[axis], 1e-7);
        }
      }
    }
  }
}

// Materials follow each body's material: glass blends and is seen from both sides, a glass
// fragment's side walls (its crack faces) are a second primitive in their own material, and
// each look is written once, in the order the meshes first use it.
TEST(Glb, MaterialsFollowTheBodysMaterialAndFragmentsCarryTheirCrackFaces) {
  engine::Result result;
  const auto add = [&](const char* name, const char* material, bool fragment) {
    engine::BodyInfo body;
    body.name = name;
    body.material = material;
    body.fragment = fragment;
    body.mass_kg = 1.0;
    body.mesh = box(0.2, 0.1, 0.003);  // a 6 mm slab, thin along z as fragments are
    result.bodies.push_back(body);
  };
  add("pane/f0", "annealed_glass", true);
  add("brick", "brick", false);
  add("pane", "tempered_glass", false);  // an unbroken pane: one primitive, glass
  add("crate", "", false);
  add("pane/f1", "glass", true);
  const Glb glb = parsed(result);
  const json& materials = glb.gltf["materials"];
  std::vector<std::string> names;
  for (const json& m : materials)
    names.push_back(m["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"glass", "glass crack faces", "brick", "default"}));
  EXPECT_EQ(materials[0]["alphaMode"], "BLEND");
  EXPECT_EQ(materials[0]["doubleSided"], true);
  EXPECT_LT(materials[0]["pbrMetallicRoughness"]["baseColorFactor"][3].get<double>(), 1.0);
  EXPECT_FALSE(materials[2].contains("alphaMode"));  // brick is opaque

  const json& meshes = glb.gltf["meshes"];
  const auto material_of = [&](std::size_t mesh, std::size_t primitive) {
    return meshes[mesh]["primitives"][primitive]["material"].get<std::size_t>();
  };
  const auto triangles = [&](std::size_t mesh, std::size_t primitive) {
    const std::size_t indices = meshes[mesh]["primitives"][primitive]["indices"];
    return glb.gltf["accessors"][indices]["count"].get<std::size_t>() / 3;
  };
  // A box of 12 triangles: 4 face the thin axis (front and back), 8 are its side walls.
  for (const std::size_t fragment : {0u, 4u}) {
    ASSERT_EQ(meshes[fragment]["primitives"].size(), 2u);
    EXPECT_EQ(material_of(fragment, 0), 0u);
    EXPECT_EQ(triangles(fragment, 0), 4u);
    EXPECT_EQ(material_of(fragment, 1), 1u);
    EXPECT_EQ(triangles(fragment, 1), 8u);
  }
  ASSERT_EQ(meshes[1]["primitives"].size(), 1u);
  EXPECT_EQ(material_of(1, 0), 2u);
  ASSERT_EQ(meshes[2]["primitives"].size(), 1u);
  EXPECT_EQ(material_of(2, 0), 0u);
  EXPECT_EQ(triangles(2, 0), 12u);
  EXPECT_EQ(material_of(3, 0), 3u);
}

TEST(Glb, NodesPivotAtTheirBodysCentreOfMassWithoutMovingAnything) {
  // A fragment's shape frame is its pane's centre: here a box whose centre of mass lies at c
  // in its shape frame, turned, and animated. Its node must sit at the centre of mass, and every
  // vertex must still land where the body puts it, at the start and in every frame.
  const geometry::Vec3 c(0.4, -0.3, 0.05);
  engine::Result result = synthetic_result();
  engine::BodyInfo& window = result.bodies[3];
  for (geometry::Vec3& vertex : window.mesh.vertices)
    vertex += c;
  const Glb glb = parsed(result);
  const auto rotation = [](const std::array<double, 4>& q) -> Eigen::Quaterniond {
    return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized();
  };
  const auto world = [&](const engine::Pose& pose, const geometry::Vec3& local) -> geometry::Vec3 {
    return geometry::Vec3(pose.position[0], pose.position[1], pose.position[2]) +
           rotation(pose.orientation) * local;
  };
  const json& node = glb.gltf["nodes"][3];
  const geometry::Vec3 com = world(window.initial_pose, c);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(node["translation"][axis].get<double>(), com[axis], 1e-12);
  // The mesh is stored about its centre of mass: a box's bounds are symmetric.
  const json& primitive = glb.gltf["meshes"][3]["primitives"][0];
  const std::size_t position = primitive["attributes"]["POSITION"];
  const json& accessor = glb.gltf["accessors"][position];
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(accessor["min"][axis].get<double>(), -accessor["max"][axis].get<double>(), 1e-6);
  // Every frame's translation sample is the centre of mass at that pose (window is slot 0).
  const json& animation = glb.gltf["animations"][0];
  std::size_t output = 0;
  for (const json& channel : animation["channels"])
    if (channel["target"]["node"] == 3 && channel["target"]["path"] == "translation")
      output = animation["samplers"][channel["sampler"].get<std::size_t>()]["output"];
  for (std::size_t f = 0; f < result.frame_times_s.size(); ++f) {
    const geometry::Vec3 expected = world(result.pose(f, 0), c);
    for (std::size_t axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(accessor_float(glb, output, f, axis), expected[static_cast<int>(axis)], 1e-6)
          << "frame " << f;
  }
  // A vertex placed by the node (translation + rotation of the stored, shifted vertex) is where
  // the body's pose puts the original one.
  const geometry::Vec3& original = window.mesh.vertices[window.mesh.triangles[0][0]];
  const geometry::Vec3 stored(accessor_float(glb, position, 0, 0),
                              accessor_float(glb, position, 0, 1),
                              accessor_float(glb, position, 0, 2));
  const geometry::Vec3 placed = com + rotation(window.initial_pose.orientation) * stored;
  EXPECT_NEAR((placed - world(window.initial_pose, original)).norm(), 0.0, 1e-6);
}

TEST(Glb, IndicesAreSixteenBitUpTo65535VerticesAndThirtyTwoBitBeyond) {
  engine::Result result;
  for (const std::size_t triangles : {std::size_t{21845}, std::size_t{21846}}) {
    engine::BodyInfo body;
    body.name = "strip" + std::to_string(triangles);
    body.mesh = strip(triangles);
    result.bodies.push_back(body);
  }
  const Glb glb = parsed(result);
  const json& accessors = glb.gltf["accessors"];
  const std::size_t small = glb.gltf["meshes"][0]["primitives"][0]["indices"];
  const std::size_t large = glb.gltf["meshes"][1]["primitives"][0]["indices"];
  EXPECT_EQ(accessors[small]["componentType"], 5123);
  EXPECT_EQ(accessors[small]["count"], 65535);
  EXPECT_EQ(accessor_index(glb, small, 65534), 65534u);
  EXPECT_EQ(accessors[large]["componentType"], 5125);
  EXPECT_EQ(accessors[large]["count"], 65538);
  EXPECT_EQ(accessor_index(glb, large, 65537), 65537u);
}

TEST(Glb, AnimationSamplesEveryAnimatedBodyAtTheFrameTimes) {
  const engine::Result result = synthetic_result();
  const Glb glb = parsed(result);
  ASSERT_EQ(glb.gltf["animations"].size(), 1u);
  const json& animation = glb.gltf["animations"][0];
  EXPECT_EQ(animation["name"], "blast");
  const json& accessors = glb.gltf["accessors"];
  ASSERT_EQ(animation["channels"].size(), 2 * result.animated.size());
  for (std::size_t k = 0; k < result.animated.size(); ++k) {
    for (const std::string path : {"translation", "rotation"}) {
      SCOPED_TRACE(path + " of animated body " + std::to_string(k));
      const json* channel = nullptr;
      for (const json& candidate : animation["channels"])
        if (candidate["target"]["node"] == result.animated[k] &&
            candidate["target"]["path"] == path)
          channel = &candidate;
      ASSERT_NE(channel, nullptr);
      const json& sampler = animation["samplers"][(*channel)["sampler"].get<std::size_t>()];
      EXPECT_EQ(sampler["interpolation"], "LINEAR");
      const std::size_t input = sampler["input"];
      const std::size_t output = sampler["output"];
      EXPECT_EQ(accessors[input]["count"], result.frame_times_s.size());
      EXPECT_EQ(accessors[input]["type"], "SCALAR");
      EXPECT_EQ(accessors[input]["min"][0].get<double>(),
                static_cast<float>(result.frame_times_s.front()));
      EXPECT_EQ(accessors[input]["max"][0].get<double>(),
                static_cast<float>(result.frame_times_s.back()));
      EXPECT_EQ(accessors[output]["count"], result.frame_times_s.size());
      EXPECT_EQ(accessors[output]["type"], path == "translation" ? "VEC3" : "VEC4");
      for (std::size_t f = 0; f < result.frame_times_s.size(); ++f) {
        EXPECT_EQ(accessor_float(glb, input, f, 0), static_cast<float>(result.frame_times_s[f]));
        const engine::Pose& pose = result.pose(f, k);
        if (path == "translation") {
          for (std::size_t c = 0; c < 3; ++c)
            EXPECT_EQ(accessor_float(glb, output, f, c), static_cast<float>(pose.position[c]));
          continue;
        }
        // The sample is the pose's rotation, possibly negated (q and -q are one rotation).
        double dot = 0.0;
        for (std::size_t c = 0; c < 4; ++c)
          dot += accessor_float(glb, output, f, c) * pose.orientation[c];
        EXPECT_NEAR(std::abs(dot), 1.0, 1e-6) << "frame " << f;
      }
    }
  }
}

TEST(Glb, RotationSamplesAreUnitAndSignContinuous) {
  const engine::Result result = synthetic_result(40);
  const Glb glb = parsed(result);
  int rotation_channels = 0;
  int flips_needed = 0;  // frames where the input itself jumps hemisphere: the test must bite
  for (const json& channel : glb.gltf["animations"][0]["channels"]) {
    if (channel["target"]["path"] != "rotation") continue;
    ++rotation_channels;
    const json& sampler = glb.gltf["animations"][0]["samplers"][channel["sampler"].get<int>()];
    const std::size_t output = sampler["output"];
    const std::size_t k = channel["target"]["node"] == result.animated[0] ? 0 : 1;
    std::array<double, 4> previous{};
    for (std::size_t f = 0; f < result.frame_times_s.size(); ++f) {
      std::array<double, 4> q{};
      double norm_squared = 0.0;
      for (std::size_t c = 0; c < 4; ++c) {
        q[c] = accessor_float(glb, output, f, c);
        norm_squared += q[c] * q[c];
      }
      EXPECT_NEAR(std::sqrt(norm_squared), 1.0, 1e-6) << "frame " << f;
      if (f > 0) {
        double dot = 0.0;
        double input_dot = 0.0;
        for (std::size_t c = 0; c < 4; ++c) {
          dot += q[c] * previous[c];
          input_dot += result.pose(f, k).orientation[c] * result.pose(f - 1, k).orientation[c];
        }
        EXPECT_GE(dot, 0.0) << "frame " << f;
        if (input_dot < 0.0) ++flips_needed;
      }
      previous = q;
    }
  }
  EXPECT_EQ(rotation_channels, 2);
  EXPECT_GT(flips_needed, 20);
}

TEST(Glb, BufferViewsLieInTheBufferAlignedWithStrideAndTargetOnlyForMeshData) {
  const Glb glb = parsed(synthetic_result());
  const std::size_t buffer_length = glb.gltf["buffers"][0]["byteLength"];
  const json& views = glb.gltf["bufferViews"];
  for (const json& view : views) {
    SCOPED_TRACE(view.dump());
    const std::size_t offset = view["byteOffset"];
    EXPECT_EQ(offset % 4, 0u);
    EXPECT_LE(offset + view["byteLength"].get<std::size_t>(), buffer_length);
    if (view.contains("byteStride")) {
      EXPECT_EQ(view["target"], 34962);
    }
  }
  // Views of vertex attributes and indices carry their target; views of animation data none.
  std::set<std::size_t> mesh_views;
  for (const json& mesh : glb.gltf["meshes"]) {
    const json& primitive = mesh["primitives"][0];
    for (const std::string attribute : {"POSITION", "NORMAL"}) {
      const std::size_t view =
          glb.gltf["accessors"][primitive["attributes"][attribute].get<int>()]["bufferView"];
      EXPECT_EQ(views[view]["target"], 34962);
      mesh_views.insert(view);
    }
    const std::size_t view = glb.gltf["accessors"][primitive["indices"].get<int>()]["bufferView"];
    EXPECT_EQ(views[view]["target"], 34963);
    EXPECT_FALSE(views[view].contains("byteStride"));
    mesh_views.insert(view);
  }
  for (const json& sampler : glb.gltf["animations"][0]["samplers"]) {
    for (const char* role : {"input", "output"}) {
      const std::size_t view =
          glb.gltf["accessors"][sampler[role].get<int>()]["bufferView"].get<std::size_t>();
      EXPECT_FALSE(views[view].contains("target"));
      EXPECT_FALSE(views[view].contains("byteStride"));
      EXPECT_EQ(mesh_views.count(view), 0u);
    }
  }
  // Every accessor fits its view and is aligned to its component size.
  for (const json& accessor : glb.gltf["accessors"]) {
    const json& view = views[accessor["bufferView"].get<std::size_t>()];
    const std::size_t component = accessor["componentType"] == 5123 ? 2 : 4;
    const std::size_t components = accessor["type"] == "SCALAR" ? 1
                                   : accessor["type"] == "VEC3" ? 3
                                                                : 4;
    const std::size_t stride = view.value("byteStride", component * components);
    const std::size_t begin = accessor["byteOffset"];
    EXPECT_EQ(begin % component, 0u);
    EXPECT_LE(begin + stride * (accessor["count"].get<std::size_t>() - 1) + component * components,
              view["byteLength"].get<std::size_t>());
  }
}

TEST(Glb, NoAnimationWithoutAnimatedBodiesOrWithOneFrame) {
  engine::Result static_only = synthetic_result(3);
  static_only.animated.clear();
  static_only.poses.clear();
  const Glb still = parsed(static_only);
  EXPECT_FALSE(still.gltf.contains("animations"));
  EXPECT_EQ(still.gltf["nodes"].size(), 4u);

  const Glb one_frame = parsed(synthetic_result(1));
  EXPECT_FALSE(one_frame.gltf.contains("animations"));
  EXPECT_EQ(one_frame.gltf["nodes"].size(), 4u);
}

TEST(Glb, EmptyResultIsAValidFileWithAnEmptyScene) {
  const Glb glb = parsed(engine::Result{});
  EXPECT_TRUE(glb.bin.empty());
  EXPECT_EQ(glb.gltf["scene"], 0);
  ASSERT_EQ(glb.gltf["scenes"].size(), 1u);
  EXPECT_FALSE(glb.gltf["scenes"][0].contains("nodes"));
  for (const char* absent :
       {"nodes", "meshes", "accessors", "bufferViews", "buffers", "animations"})
    EXPECT_FALSE(glb.gltf.contains(absent)) << absent;
}

}  // namespace
}  // namespace brisance::io
