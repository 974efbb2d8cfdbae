// fuzz_fracture: `brisance fracture` with fuzzed flags, through the command itself (its flag
// parsing, validation, engine::pane_pattern and the crack tree) into a JSON file that is read
// back. Bad flags must be a UsageError, never a crash; a pattern written must partition the pane
// (fragment areas sum to width x height). Sizes are bounded so one input stays fast: the grid
// is at most 128 cells, so a pattern has at most a few thousand fragments.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli/commands.hpp"

namespace {

// A flag's value: mostly a number in [lo, hi], sometimes anything (to reach the flag parser's
// and the validation's refusals).
std::string value(FuzzedDataProvider& in, double lo, double hi) {
  switch (in.ConsumeIntegralInRange(0, 15)) {
    case 0:
      return in.ConsumeRandomLengthString(24);
    case 1:
      return std::to_string(in.ConsumeFloatingPoint<double>());
    case 2:
      return "0";
    case 3:
      return "-1";
    default: {
      std::ostringstream text;
      text.precision(17);
      text << in.ConsumeFloatingPointInRange(lo, hi);
      return text.str();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  static const std::string path_json =
      "/tmp/brisance-fuzz-fracture-" + std::to_string(getpid()) + ".json";
  static const std::string path_svg =
      "/tmp/brisance-fuzz-fracture-" + std::to_string(getpid()) + ".svg";
  std::vector<std::string> words;
  const auto flag = [&](const char* name, double lo, double hi) {
    if (!in.ConsumeBool()) return;
    words.push_back(name);
    words.push_back(value(in, lo, hi));
  };
  // width and height are nearly always given, so most inputs get past the required flags.
  if (in.ConsumeIntegralInRange(0, 31) != 0) {
    words.push_back("--width");
    words.push_back(value(in, 0.01, 4.0));
    words.push_back("--height");
    words.push_back(value(in, 0.01, 4.0));
  }
  flag("--thickness", 0.001, 0.05);
  flag("--pressure-kpa", 0.1, 1e5);
  // The dynamic breakage model (the default) needs the pulse's duration: nearly always given,
  // so most inputs reach the plate model; sometimes its impulse too, or the static model.
  if (in.ConsumeIntegralInRange(0, 15) != 0) {
    words.push_back("--duration-ms");
    words.push_back(value(in, 0.01, 100.0));
  }
  flag("--impulse-kpa-ms", 0.01, 1e4);
  if (in.ConsumeIntegralInRange(0, 3) == 0) {
    words.push_back("--breakage");
    switch (in.ConsumeIntegralInRange(0, 4)) {
      case 0:
        words.push_back(in.ConsumeRandomLengthString(12));
        break;
      case 1:
        words.push_back("dynamic");
        break;
      default:
        words.push_back("static");
    }
  }
  flag("--growth-length", 0.001, 2.0);
  flag("--branch-angle-deg", -10.0, 200.0);
  flag("--angle-variance-deg", -10.0, 400.0);
  flag("--wiggle-prob", -0.5, 1.5);
  flag("--wiggle-deg", -10.0, 400.0);
  flag("--initial-crack", 0.0, 2.0);
  flag("--seed", 0.0, 1e6);
  // The grid is bounded (the command allows 4..kMaxGridCells) so that one input stays fast.
  const bool grid_given = in.ConsumeIntegralInRange(0, 7) != 0;
  if (grid_given) {
    words.push_back("--grid");
    words.push_back(std::to_string(in.ConsumeIntegralInRange(-2, 128)));
  }
  const bool svg = in.ConsumeBool();
  words.push_back("-o");
  words.push_back(svg ? path_svg : path_json);
  if (!grid_given) return 0;  // the default grid of 2048 cells is too slow for fuzzing

  // BRISANCE_FUZZ_PRINT=1: the command line of each input, to reproduce a finding with the CLI.
  static const bool print = std::getenv("BRISANCE_FUZZ_PRINT") != nullptr;
  if (print) {
    std::string line = "brisance fracture";
    for (const std::string& word : words)
      line += " '" + word + "'";
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  brisance::cli::Args args(words.begin(), words.end());
  std::ostringstream out;
  try {
    if (brisance::cli::run_fracture(args, out) != brisance::cli::kExitOk) std::abort();
  } catch (const brisance::cli::UsageError& error) {
    if (error.message.empty()) std::abort();
    return 0;
  }
  if (svg) return 0;
  std::ifstream file(path_json);
  const nlohmann::json pattern = nlohmann::json::parse(file);
  const double pane_area = pattern.at("width").get<double>() * pattern.at("height").get<double>();
  // A pane of 1e200 m has no finite area (nor stress): its JSON holds nulls, and there is
  // nothing to sum. Noted in bench/results/fuzz.txt; every finite pane is checked.
  if (!std::isfinite(pane_area)) return 0;
  double area = 0.0;
  for (const nlohmann::json& fragment : pattern.at("fragments")) {
    const double a = fragment.at("area").get<double>();
    if (!(a > 0.0)) std::abort();
    area += a;
  }
  if (!(std::abs(area - pane_area) <= 1e-9 + 1e-9 * pane_area)) std::abort();
  return 0;
}
