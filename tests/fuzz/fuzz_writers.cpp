// fuzz_writers: a small scene made from the bytes (one to three boxes with fuzzed sizes,
// positions, masses and anchoring, a charge of fuzzed mass and place, maybe a window pane that
// breaks, a short run), validated and simulated; its BRF1 frames and its glb are then written and
// read back. BRF1: the header's counts give exactly the length written, every time and pose is
// finite. glb: the header's length is the file's, the JSON and BIN chunks fill it exactly, the
// JSON chunk parses, and every buffer view and accessor lies inside the binary chunk.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>
#include <nlohmann/json.hpp>

#include "sim/engine/simulator.hpp"
#include "sim/io/frames.hpp"
#include "sim/io/gltf.hpp"
#include "sim/scene/scene.hpp"

namespace {

using nlohmann::json;

void check(bool condition) {
  if (!condition) std::abort();
}

template <typename T>
T read_le(const std::uint8_t* at) {
  T value;
  std::memcpy(&value, at, sizeof value);  // the writers and this machine are little-endian
  return value;
}

json vec3(FuzzedDataProvider& in, double lo, double hi) {
  return json::array({in.ConsumeFloatingPointInRange(lo, hi),
                      in.ConsumeFloatingPointInRange(lo, hi),
                      in.ConsumeFloatingPointInRange(lo, hi)});
}

// Every object and the charge stand on or above the ground (at height 0 unless the scene has
// none): positions drawn anywhere in [-4, 4] put 93 % of the scenes below it, and the validator
// refused them before anything was simulated or written (fuzz_scene covers the validator).
json above_ground(FuzzedDataProvider& in, double half_height) {
  const double x = in.ConsumeFloatingPointInRange(-4.0, 4.0);
  const double y = half_height + in.ConsumeFloatingPointInRange(0.0, 3.0);
  const double z = in.ConsumeFloatingPointInRange(-4.0, 4.0);
  return json::array({x, y, z});
}

json scene_from(FuzzedDataProvider& in) {
  json objects = json::array();
  const int boxes = in.ConsumeIntegralInRange(1, 3);
  for (int i = 0; i < boxes; ++i) {
    const json size = vec3(in, 0.02, 2.0);
    json box = {{"name", "box" + std::to_string(i)},
                {"shape", {{"type", "box"}, {"size", size}}},
                {"position", above_ground(in, 0.5 * size[1].get<double>())}};
    if (in.ConsumeBool()) {
      box["mass"] = in.ConsumeFloatingPointInRange(0.01, 1000.0);
    } else {
      box["material"] = in.PickValueInArray({"wood", "concrete", "steel", "brick"});
    }
    if (in.ConsumeIntegralInRange(0, 3) == 0) box["anchored"] = true;
    if (in.ConsumeBool()) box["rotates"] = false;
    objects.push_back(std::move(box));
  }
  if (in.ConsumeIntegralInRange(0, 3) == 0) {
    // A small pane that always breaks, on a coarse grid (the scene's coarsest is 16 cells: 8 to
    // 15 were refused, a quarter of the panes), so fragments fly too; sometimes held by a frame
    // along its edges (docs/scene-format.md: a breakable pane is never anchored). Its growth
    // length is given, 1 to 10 cm: from the stress, a pane beside a large charge breaks at the
    // finest scale (1 786 fragments and a 25 MB glb for this 0.3 x 0.2 m pane: 1.5 s in a
    // release build, over the 60 s timeout under the sanitizers), which tests the writers no
    // better than a few dozen.
    objects.push_back({{"name", "pane"},
                       {"shape", {{"type", "box"}, {"size", {0.3, 0.2, 0.006}}}},
                       {"position", above_ground(in, 0.1)},
                       {"material", "glass"},
                       {"fracture",
                        {{"break", "always"},
                         {"framed", in.ConsumeBool()},
                         {"growth_length", in.ConsumeFloatingPointInRange(0.01, 0.1)},
                         {"grid", in.ConsumeIntegralInRange(16, 64)}}}});
  }
  json scene = {{"charges", json::array({{{"position", above_ground(in, 0.0)},
                                          {"mass", in.ConsumeFloatingPointInRange(0.01, 100.0)},
                                          {"burst", in.ConsumeBool() ? "air" : "surface"}}})},
                {"objects", std::move(objects)},
                {"simulation",
                 {{"duration", in.ConsumeFloatingPointInRange(0.01, 0.25)},
                  {"frame_rate", in.ConsumeFloatingPointInRange(5.0, 120.0)},
                  {"seed", in.ConsumeIntegral<std::uint32_t>()}}}};
  if (in.ConsumeBool()) scene["environment"] = {{"ground", nullptr}};
  return scene;
}

void check_brf1(const std::string& bytes, const brisance::io::FrameSet& frames) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  check(bytes.size() >= 16 && std::memcmp(b, "BRF1", 4) == 0);
  check(read_le<std::uint32_t>(b + 4) == frames.first_frame);
  const std::uint64_t frame_count = read_le<std::uint32_t>(b + 8);
  const std::uint64_t body_count = read_le<std::uint32_t>(b + 12);
  check(frame_count == frames.frame_count() && body_count == frames.bodies.size());
  check(bytes.size() == 16 + 4 * body_count + frame_count * (8 + 28 * body_count));
  const std::uint8_t* at = b + 16 + 4 * body_count;
  double previous_time = -1.0;
  for (std::uint64_t f = 0; f < frame_count; ++f) {
    const double time = read_le<double>(at);
    check(std::isfinite(time) && time > previous_time);
    previous_time = time;
    at += 8;
    for (std::uint64_t k = 0; k < 7 * body_count; ++k, at += 4)
      check(std::isfinite(read_le<float>(at)));
  }
}

void check_glb(const std::vector<std::uint8_t>& glb) {
  const std::uint8_t* b = glb.data();
  check(glb.size() >= 28 && std::memcmp(b, "glTF", 4) == 0);
  check(read_le<std::uint32_t>(b + 4) == 2);
  check(read_le<std::uint32_t>(b + 8) == glb.size());
  const std::size_t json_length = read_le<std::uint32_t>(b + 12);
  check(std::memcmp(b + 16, "JSON", 4) == 0 && json_length % 4 == 0);
  check(20 + json_length + 8 <= glb.size());
  const json document =
      json::parse(std::string(reinterpret_cast<const char*>(b + 20), json_length));
  const std::uint8_t* bin = b + 20 + json_length;
  const std::size_t bin_length = read_le<std::uint32_t>(bin);
  check(std::memcmp(bin + 4, "BIN\0", 4) == 0 && bin_length % 4 == 0);
  check(20 + json_length + 8 + bin_length == glb.size());
  check(document.at("buffers").size() == 1);
  const std::size_t buffer_length = document.at("buffers")[0].at("byteLength");
  check(buffer_length <= bin_length && bin_length - buffer_length < 4);
  const json& views = document.at("bufferViews");
  for (const json& view : views)
    check(view.value("byteOffset", std::size_t{0}) + view.at("byteLength").get<std::size_t>() <=
          buffer_length);
  for (const json& accessor : document.at("accessors")) {
    const json& view = views.at(accessor.at("bufferView").get<std::size_t>());
    const std::size_t count = accessor.at("count");
    check(count > 0);
    const std::string type = accessor.at("type");
    const std::size_t components = type == "SCALAR" ? 1
                                   : type == "VEC3" ? 3
                                   : type == "VEC4" ? 4
                                                    : 0;
    check(components > 0);
    const int component_type = accessor.at("componentType");
    const std::size_t component_size = component_type == 5126 || component_type == 5125 ? 4 : 2;
    const std::size_t element = components * component_size;
    const std::size_t stride = view.value("byteStride", element);
    check(stride >= element);
    check(accessor.value("byteOffset", std::size_t{0}) + (count - 1) * stride + element <=
          view.at("byteLength").get<std::size_t>());
  }
  for (const json& node : document.at("nodes")) {
    if (!node.contains("mesh")) continue;
    check(node.at("mesh").get<std::size_t>() < document.at("meshes").size());
  }
}

struct SceneCounts {
  std::uint64_t inputs = 0;
  std::uint64_t valid = 0;
  std::map<std::string, std::uint64_t> refused_at;  // first error's pointer, indices dropped
};
SceneCounts counts;

void print_counts() {
  std::fprintf(
      stderr, "fuzz_writers: %llu inputs, %llu valid scenes (%.1f %%)\n",
      static_cast<unsigned long long>(counts.inputs), static_cast<unsigned long long>(counts.valid),
      counts.inputs ? 100.0 * static_cast<double>(counts.valid) / static_cast<double>(counts.inputs)
                    : 0.0);
  for (const auto& [pointer, n] : counts.refused_at)
    std::fprintf(stderr, "  refused at %s: %llu\n", pointer.c_str(),
                 static_cast<unsigned long long>(n));
}

void count_scene(const brisance::scene::ParseResult& parsed) {
  if (counts.inputs++ == 0) std::atexit(print_counts);
  if (parsed.scene) {
    ++counts.valid;
    return;
  }
  std::string pointer;
  for (char c : parsed.errors.front().pointer)
    if (c < '0' || c > '9') pointer += c;
  ++counts.refused_at[pointer];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const json document = scene_from(in);
  // BRISANCE_FUZZ_PRINT=1: each input's scene, to reproduce a finding with `brisance run`.
  static const bool print = std::getenv("BRISANCE_FUZZ_PRINT") != nullptr;
  if (print) std::fprintf(stderr, "%s\n", document.dump().c_str());
  const brisance::scene::ParseResult parsed = brisance::scene::parse_scene(document);
  // BRISANCE_FUZZ_STATS=1: at exit, how many inputs made a valid scene (what this target is
  // for) and the first error pointer of the others, most frequent first.
  static const bool stats = std::getenv("BRISANCE_FUZZ_STATS") != nullptr;
  if (stats) count_scene(parsed);
  if (!parsed.scene) return 0;  // overlapping boxes and the like: the validator's business
  const brisance::engine::RunOutcome run = brisance::engine::simulate(*parsed.scene);
  check(!run.cancelled);
  const brisance::io::FrameSet frames = brisance::io::frames_of(run.result);
  check_brf1(brisance::io::frames_to_brf1(frames), frames);
  check_glb(brisance::io::result_to_glb(run.result));
  return 0;
}
