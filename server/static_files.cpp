#include "server/static_files.hpp"

#include <fstream>
#include <sstream>

namespace brisance::server {

std::string_view content_type_for(std::string_view path) {
  static const std::pair<std::string_view, std::string_view> kTypes[] = {
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".ico", "image/x-icon"},
      {".woff2", "font/woff2"},
      {".glb", "model/gltf-binary"},
      {".wasm", "application/wasm"},
      {".txt", "text/plain; charset=utf-8"},
  };
  for (const auto& [extension, type] : kTypes) {
    if (path.size() >= extension.size() &&
        path.substr(path.size() - extension.size()) == extension) {
      return type;
    }
  }
  return "application/octet-stream";
}

StaticFiles::StaticFiles(std::filesystem::path root) : root_(std::move(root)) {}

bool StaticFiles::available() const {
  std::error_code ec;
  return std::filesystem::is_regular_file(root_ / "index.html", ec);
}

std::optional<std::pair<std::string, std::string>> StaticFiles::get(
    std::string_view relative_path) {
  // Only plain relative paths inside the root: no "..", no absolute paths, no backslashes.
  if (relative_path.empty() || relative_path.front() == '/' ||
      relative_path.find('\\') != std::string_view::npos ||
      relative_path.find('\0') != std::string_view::npos) {
    return std::nullopt;
  }
  for (std::string_view rest = relative_path; !rest.empty();) {
    const auto slash = rest.find('/');
    const std::string_view part = rest.substr(0, slash);
    if (part == ".." || part == "." || part.empty()) return std::nullopt;
    if (slash == std::string_view::npos) break;
    rest.remove_prefix(slash + 1);
  }
  {
    std::lock_guard lock(mutex_);
    if (auto it = cache_.find(relative_path); it != cache_.end()) return it->second;
  }
  const std::filesystem::path file = root_ / std::filesystem::path(std::string(relative_path));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::pair<std::string, std::string> entry{std::string(content_type_for(relative_path)),
                                            bytes.str()};
  std::lock_guard lock(mutex_);
  cache_.emplace(std::string(relative_path), entry);
  return entry;
}

}  // namespace brisance::server
