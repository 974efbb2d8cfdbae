// fuzz_scene: any bytes as scene JSON text through the parser and validator with the default
// limits. It must never crash, abort or leak; a rejected scene has at least one error and every
// error carries a JSON pointer ("" for the document itself) and a message.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "sim/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const brisance::scene::ParseResult result = brisance::scene::parse_scene_text(text);
  if (result.scene.has_value() != result.errors.empty()) std::abort();
  for (const brisance::scene::ValidationError& error : result.errors) {
    if (!error.pointer.empty() && error.pointer.front() != '/') std::abort();
    if (error.message.empty()) std::abort();
  }
  return 0;
}
