// server/routes/assets: uploaded mesh files — POST /v1/assets (the raw file; its format from the
// `format` parameter or the media type) and GET /v1/assets/{id}. Scenes name an asset with
// {"type": "asset", "asset": ID, "node": ...}; like jobs, an asset is seen only by its key.
#include <nlohmann/json.hpp>

#include "server/log.hpp"
#include "server/routes/routes.hpp"

namespace brisance::server::routes {

namespace {

using nlohmann::json;

std::string asset_path(std::string_view id) {
  return "/v1/assets/" + std::string(id);
}

std::string asset_json(const AssetRecord& asset) {
  json nodes = json::parse(asset.nodes_json, nullptr, false);
  if (!nodes.is_array()) nodes = json::array();
  return json{{"id", asset.id},
              {"format", asset.format},
              {"size_bytes", asset.size_bytes},
              {"nodes", std::move(nodes)},
              {"created_at", iso_time_utc(asset.created_ms)},
              {"links", {{"self", asset_path(asset.id)}}}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

// The IANA media types of the formats (model/gltf-binary, model/gltf+json, model/obj);
// parameters such as "; charset=" are ignored.
std::optional<io::MeshFormat> format_of_media_type(std::string_view content_type) {
  const auto semicolon = content_type.find(';');
  std::string type(content_type.substr(0, semicolon));
  while (!type.empty() && type.back() == ' ')
    type.pop_back();
  for (char& ch : type)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  if (type == "model/gltf-binary") return io::MeshFormat::glb;
  if (type == "model/gltf+json") return io::MeshFormat::gltf;
  if (type == "model/obj") return io::MeshFormat::obj;
  return std::nullopt;
}

HttpResponse asset_not_found(std::string_view id) {
  return problem(404, "not-found", "Asset not found",
                 "no asset " + std::string(id) +
                     " (assets are seen only by the key that uploaded "
                     "them)")
      .response();
}

}  // namespace

HttpResponse upload_asset(const Context& c) {
  std::optional<io::MeshFormat> format;
  if (auto name = c.target.get("format")) {
    format = io::parse_mesh_format(*name);
    if (!format) throw BadParameter{"format", "'format' must be one of glb, gltf, obj"};
  } else {
    format = format_of_media_type(c.request.header("content-type"));
    if (!format) {
      return problem(415, "unsupported-media-type", "Unsupported media type",
                     "send the mesh file as model/gltf-binary (.glb), model/gltf+json (.gltf with "
                     "embedded buffers) or model/obj, or name it with ?format=glb|gltf|obj")
          .response();
    }
  }
  const AssetOutcome outcome =
      c.service.upload_asset({c.request.body, *format, c.key ? std::string_view(c.key->name) : ""});
  switch (outcome.kind) {
    case AssetOutcome::Kind::too_large:
      return problem(413, "payload-too-large", "Asset too large", outcome.message).response();
    case AssetOutcome::Kind::invalid:
      return problem(422, "invalid-asset", "Invalid asset", outcome.message).response();
    case AssetOutcome::Kind::created:
    case AssetOutcome::Kind::existing: {
      HttpResponse r = json_text_response(outcome.kind == AssetOutcome::Kind::created ? 201 : 200,
                                          asset_json(outcome.asset));
      r.headers.emplace_back("Location", asset_path(outcome.asset.id));
      return r;
    }
  }
  return problem(500, "internal-error", "Internal error", "unknown upload outcome").response();
}

HttpResponse get_asset(const Context& c) {
  const auto asset = c.service.asset(c.id, c.owner_filter());
  if (!asset) return asset_not_found(c.id);
  HttpResponse r = json_text_response(200, asset_json(*asset));
  // The id is the content's hash: an asset never changes.
  r.headers.emplace_back("Cache-Control", "private, max-age=31536000, immutable");
  return r;
}

}  // namespace brisance::server::routes
