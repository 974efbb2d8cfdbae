// server/free_space: see free_space.hpp.
#include "server/free_space.hpp"

namespace brisance::server {

FreeSpace::FreeSpace(std::filesystem::path folder, std::uint64_t floor_bytes)
    : folder_(std::move(folder)), floor_bytes_(floor_bytes) {}

void FreeSpace::refresh() {
  const auto now = std::chrono::steady_clock::now();
  if (checked_ != std::chrono::steady_clock::time_point{} &&
      now - checked_ < std::chrono::seconds(1))
    return;
  checked_ = now;
  std::error_code error;
  const std::filesystem::space_info info = std::filesystem::space(folder_, error);
  readable_ = !error;
  available_ = error ? 0 : info.available;
}

bool FreeSpace::low() {
  if (floor_bytes_ == 0) return false;
  std::lock_guard lock(mutex_);
  refresh();
  return !readable_ || available_ < floor_bytes_;
}

std::uint64_t FreeSpace::available_bytes() {
  std::lock_guard lock(mutex_);
  refresh();
  return available_;
}

}  // namespace brisance::server
