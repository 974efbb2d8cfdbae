// Tests of sim/io/result_codec and of the glb writer's view entry point: the stored summary,
// the meshes document and the glb of a small constructed result, pinned byte for byte (the
// bytes the service stored and served before the codec existed).
#include "sim/io/result_codec.hpp"

#include <cstring>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/io/frames.hpp"
#include "sim/io/gltf.hpp"

namespace brisance::io {
namespace {

using nlohmann::json;

// Body 0: one triangle, animated over two frames; body 1: no mesh, static. Every number is
// exact in float32, as the service's stored rows are.
engine::Result small_result() {
  engine::Result result;
  engine::BodyInfo shard;
  shard.name = "shard";
  shard.material = "annealed_glass";
  shard.fragment = true;
  shard.mass_kg = 2.5;
  shard.mesh.vertices = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.5, 0.0}};
  shard.mesh.triangles = {{0, 1, 2}};
  shard.initial_pose.position = {0.0, 1.0, 2.0};
  result.bodies.push_back(shard);
  engine::BodyInfo marker;
  marker.name = "marker";
  marker.mass_kg = 1.0;
  marker.initial_pose.position = {-1.0, 0.0, 0.25};
  marker.initial_pose.orientation = {0.0, 0.0, 1.0, 0.0};
  result.bodies.push_back(marker);
  result.animated = {0};
  result.frame_times_s = {0.0, 0.5};
  engine::Pose later;
  later.position = {0.0, 1.5, 2.0};
  later.orientation = {0.5, 0.5, 0.5, 0.5};
  result.poses = {shard.initial_pose, later};
  result.final_state = {{"shard", later, {0.0, 1.0, 0.0}, {0.0, 0.0, 0.5}},
                        {"marker", marker.initial_pose, {}, {}}};
  result.stats.steps = 40;
  result.stats.simulated_time_s = 0.5;
  result.stats.wall_time_s = 0.125;
  result.stats.bodies = 2;
  result.stats.bodies_static_in_frames = 1;
  result.stats.panels = 7;
  result.stats.panels_loaded = 1;
  result.stats.body_steps = 40;
  result.warnings = {{"blast_out_of_range", "far away", 3}};
  return result;
}

std::string hex(const std::uint8_t* bytes, std::size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < size; ++i) {
    out += kDigits[bytes[i] >> 4];
    out += kDigits[bytes[i] & 0xf];
  }
  return out;
}

TEST(ResultCodec, SummaryIsPinned) {
  EXPECT_EQ(result_summary(small_result()).dump(),
            "{\"animated\":[0],\"bodies\":[{\"animated\":true,\"fragment\":true,\"index\":0,\"ma"
            "ss\":2.5,\"material\":\"annealed_glass\",\"name\":\""
            "shard\",\"orientation\":[0.0,0.0,0.0,1.0],\"position\":[0.0,1.0,2.0]},{\"animated\":"
            "false,\"fragment\":false,\"index\":1,\"mass\":1.0,\"material\":\"\",\"name\":\"ma"
            "rker\",\"orientation\":[0.0,0.0,1.0,0.0]"
            ",\"position\":[-1.0,0.0,0.25]}],\"duration\":0.5,\"final_state\":[{\"angular_velocit"
            "y\":[0.0,0.0,0.5],\"linear_velocity\":[0.0,1.0,0.0],\"name\":\"shard\",\"orientation"
            "\":[0.5,0.5,0.5,0.5],\"position\":[0.0,1.5,2.0]},{\"angular_velocity\":[0.0,0.0,0.0]"
            ",\"linear_velocity\":[0.0,0.0,0.0],\"name\":\"marker\",\"orientation\":[0.0,0.0,1.0,"
            "0.0],\"position\":[-1.0,0.0,0.25]}],\"fracture\":[],\"frame_count\":2,\"frame_times\""
            ":[0.0,0.5],\"shielding\":[],\"stats\":{\"bodies\":2,\"bodies_anchored\":0,\"bodies_"
            "never_released\":0"
            ",\"bodies_slept\":0,\"bodies_static_in_frames\":1,\"body_steps\":40,\"collision_pai"
            "rs\":0,\"collision_pairs_skipped\":0,\"contact_points\":0,\"ended_early\":"
            "false,\"fragments\":0,\"fragments_held_by_frame\":0,\"occlusion_skipped\":true,"
            "\"panels\":7,\"panels_back_facing\""
            ":0,\"panels_loaded\":1,\"panels_merged\":0,\"panels_not_reached\":0,\"panels_"
            "shielded\":0,\"panes_broken"
            "\":0,\"panes_not_broke"
            "n\":0,\"simulated_time_s\":0.5,\"steps\":40,\"wall_time_s\":0.125},\"warnings\":[{\""
            "code\":\"blast_out_of_range\",\"count\":3,\"message\":\"far away\"}]}");
}

TEST(ResultCodec, MeshesDocumentIsPinned) {
  const engine::Result result = small_result();
  EXPECT_EQ(meshes_document_json(result.bodies, {true, false}),
            "{\"bodies\":[{\"animated\":true,\"fragment\":true,\"index\":0,\"mass\":2.5,\"materi"
            "al\":\"annealed_glass\",\"mesh\":{\"triangles\":[[0"
            ",1,2]],\"vertices\":[[0.0,0.0,0.0],[1.0,0.0,0.0],[0.0,0.5,0.0]]},\"name\":\"shard\","
            "\"orientation\":[0.0,0.0,0.0,1.0],\"position\":[0.0,1.0,2.0]},{\"animated\":false,\""
            "fragment\":false,\"index\":1,\"mass\":1.0,\"material\":\"\",\"mesh\":{\"triangles\":[]"
            ",\"vertices\":[]},\"name\":\"marker"
            "\",\"orientation\":[0.0,0.0,1.0,0.0],\"position\":[-1.0,0.0,0.25]}]}");
}

TEST(ResultCodec, AnimatedFlagsMarkTheListedBodies) {
  const std::vector<std::uint32_t> animated = {3, 0};
  EXPECT_EQ(animated_flags(5, animated), (std::vector<bool>{true, false, false, true, false}));
  EXPECT_EQ(animated_flags(2, {}), (std::vector<bool>{false, false}));
}

TEST(ResultCodec, GlbIsPinned) {
  const std::vector<std::uint8_t> glb = result_to_glb(small_result());
  ASSERT_GE(glb.size(), 20u);
  std::uint32_t header[5];
  std::memcpy(header, glb.data(), sizeof header);
  EXPECT_EQ(header[0], 0x46546C67u);  // "glTF"
  EXPECT_EQ(header[2], glb.size());
  const std::size_t json_length = header[3];
  ASSERT_LE(20 + json_length + 8, glb.size());
  const std::string json_chunk(reinterpret_cast<const char*>(glb.data()) + 20, json_length);
  // The shard's node sits at its centre of mass (the triangle's centroid, 1/3 and 1/6 along x
  // and y from its shape origin at (0, 1, 2)); its vertices and samples are shifted to match.
  EXPECT_EQ(json_chunk,
            "{\"accessors\":[{\"bufferView\":0,\"byteOffset\":0,\"componentType\":5126,\"count\":3,"
            "\"max\":[0.6666666865348816,0.3333333432674408,0.0],\"min\":[-0.3333333432674408,-0.16"
            "66666716337204,0.0],\"type\":\"VEC3\"},{\"bufferView\":1,\"byteOffset\":0,\"componentT"
            "ype\":5126,\"count\":3,\"type\":\"VEC3\"},{\"bufferView\":2,\"byteOffset\":0,\"compone"
            "ntType\":5123,\"count\":3,\"type\":\"SCALAR\"},{\"bufferView\":3,\"byteOffset\":0,\"co"
            "mponentType\":5126,\"count\":2,\"max\":[0.5],\"min\":[0.0],\"type\":\"SCALAR\"},{\"buf"
            "ferView\":4,\"byteOffset\":0,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},{\""
            "bufferView\":5,\"byteOffset\":0,\"componentType\":5126,\"count\":2,\"type\":\"VEC4\"}]"
            ",\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"trans"
            "lation\"}},{\"sampler\":1,\"target\":{\"node\":0,\"path\":\"rotation\"}}],\"name\":\"b"
            "last\",\"samplers\":[{\"input\":3,\"interpolation\":\"LINEAR\",\"output\":4},{\"input"
            "\":3,\"interpolation\":\"LINEAR\",\"output\":5}]}],\"asset\":{\"generator\":\"Brisance"
            "\",\"version\":\"2.0\"},\"bufferViews\":[{\"buffer\":0,\"byteLength\":36,\"byteOffset"
            "\":0,\"byteStride\":12,\"target\":34962},{\"buffer\":0,\"byteLength\":36,\"byteOffset"
            "\":36,\"byteStride\":12,\"target\":34962},{\"buffer\":0,\"byteLength\":6,\"byteOffset"
            "\":72,\"target\":34963},{\"buffer\":0,\"byteLength\":8,\"byteOffset\":80},{\"buffer\":"
            "0,\"byteLength\":24,\"byteOffset\":88},{\"buffer\":0,\"byteLength\":32,\"byteOffset\":"
            "112}],\"buffers\":[{\"byteLength\":144}],\"materials\":[{\"alphaMode\":\"BLEND\",\"dou"
            "bleSided\":true,\"name\":\"glass\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.62"
            ",0.8,0.86,0.3],\"metallicFactor\":0.0,\"roughnessFactor\":0.05}}],\"meshes\":[{\"name"
            "\":\"shard\",\"primitives\":[{\"attributes\":{\"NORMAL\":1,\"POSITION\":0},\"indices\""
            ":2,\"material\":0,\"mode\":4}]}],\"nodes\":[{\"mesh\":0,\"name\":\"shard\",\"rotation"
            "\":[0.0,0.0,0.0,1.0],\"translation\":[0.3333333333333333,1.1666666666666667,2.0]},{\"n"
            "ame\":\"marker\",\"rotation\":[0.0,0.0,1.0,0.0],\"translation\":[-1.0,0.0,0.25]}],\"sc"
            "ene\":0,\"scenes\":[{\"nodes\":[0,1]}]}   ");
  const std::size_t bin = 20 + json_length;
  EXPECT_EQ(hex(glb.data() + bin, glb.size() - bin),
            "9000000042494e00abaaaabeabaa2abe00000000abaa2a3fabaa2abe00000000abaaaabeabaaaa3e"
            "0000000000000000000000000000803f00000000000000000000803f00000000000000000000803f"
            "0000010002000000000000000000003fabaaaa3e5555953f0000004000000000abaaea3fabaa0a40"
            "0000000000000000000000000000803f0000003f0000003f0000003f0000003f");
}

TEST(ResultCodec, GlbOfTheViewEqualsTheGlbOfTheResult) {
  const engine::Result result = small_result();
  EXPECT_EQ(to_glb(result.bodies, frames_of(result)), result_to_glb(result));
}

}  // namespace
}  // namespace brisance::io
