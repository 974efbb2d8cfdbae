// sim/io/mesh_import: triangle meshes from glTF 2.0 (.gltf, .glb) and Wavefront OBJ files, for
// the scene's `file` and `asset` shapes (docs/scene-format.md). One importer, Debian's assimp,
// reads both formats; it stays inside mesh_import.cpp, so nothing that includes this header sees
// it. Units: glTF is metres by definition; OBJ has none and is taken as metres too.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/geometry/mesh.hpp"

namespace brisance::io {

enum class MeshFormat { glb, gltf, obj };

std::string_view to_string(MeshFormat format);  // "glb", "gltf", "obj"
// "glb", "gltf" or "obj" (any case); nullopt for anything else.
std::optional<MeshFormat> parse_mesh_format(std::string_view name);
// From a file name's extension (.glb, .gltf, .obj, any case).
std::optional<MeshFormat> mesh_format_of_path(const std::filesystem::path& path);

// What an import gives: the mesh (vertices at the same position joined, in metres, in the frame
// of the chosen node or of the file), the names of the nodes that hold geometry (depth first, in
// file order) and, when it failed, why.
struct MeshImport {
  std::optional<geometry::TriangleMesh> mesh;  // set when `error` is empty
  std::vector<std::string> nodes;
  std::string error;
};

// `node` empty: every mesh of the file, placed by its nodes' transforms in the file's frame.
// `node` given: the meshes of that node and the nodes below it, in that node's own frame (its
// own transform dropped, so the object's position and orientation place the node's origin);
// a name that no node has is an error listing the names there are. Points and lines are
// ignored; polygons are triangulated. The mesh is not checked for closedness here
// (geometry::check_closed_mesh does that).
MeshImport import_mesh(std::string_view bytes, MeshFormat format,
                       std::optional<std::string_view> node = std::nullopt);
// The same from a file; a .gltf may refer to .bin buffers next to it.
MeshImport import_mesh_file(const std::filesystem::path& path,
                            std::optional<std::string_view> node = std::nullopt);

}  // namespace brisance::io
