// server/free_space: the free space of the data folder against a floor, so the service refuses
// new work (507) and reports itself not ready before the disk is full, while deletes and cancels
// (which need little room) still work and can make space.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>

namespace brisance::server {

class FreeSpace {
 public:
  // floor_bytes 0: never low.
  FreeSpace(std::filesystem::path folder, std::uint64_t floor_bytes);

  // Whether the folder's filesystem has less than the floor available (checked at most once a
  // second); a folder whose space cannot be read counts as low.
  bool low();
  std::uint64_t available_bytes();
  std::uint64_t floor_bytes() const { return floor_bytes_; }

 private:
  void refresh();

  std::filesystem::path folder_;
  std::uint64_t floor_bytes_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point checked_{};
  std::uint64_t available_ = 0;
  bool readable_ = true;
};

}  // namespace brisance::server
