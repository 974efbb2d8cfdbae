// server/static_files: the dashboard's built files (web/dist) served from a folder, read once
// and kept in memory; paths that leave the folder are refused.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace brisance::server {

class StaticFiles {
 public:
  explicit StaticFiles(std::filesystem::path root);
  // (content type, bytes) of `relative_path` ("index.html", "assets/app.js"), or nullopt.
  std::optional<std::pair<std::string, std::string>> get(std::string_view relative_path);
  bool available() const;
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
  std::mutex mutex_;
  std::map<std::string, std::pair<std::string, std::string>, std::less<>> cache_;
};

std::string_view content_type_for(std::string_view path);

}  // namespace brisance::server
