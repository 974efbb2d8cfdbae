// sim/io/mesh_import: glTF and OBJ through assimp (Debian's libassimp-dev). assimp was chosen
// over tinygltf because one library reads both formats; tinygltf reads glTF only and OBJ would
// need a second library.
#include "sim/io/mesh_import.hpp"

#include <cstdint>
#include <map>
#include <tuple>

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace brisance::io {

namespace {

// Triangulated, with point and line primitives dropped. Vertices are not joined by assimp
// (aiProcess_JoinIdenticalVertices keeps vertices apart that differ in normal or texture
// coordinate, as a flat-shaded crate's do); collect() joins them by position.
constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_SortByPType;

Eigen::Affine3d to_affine(const aiMatrix4x4& m) {
  Eigen::Matrix4d matrix;
  matrix << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2,
      m.d3, m.d4;
  return Eigen::Affine3d(matrix);
}

bool has_geometry(const aiNode& node) {
  if (node.mNumMeshes > 0) return true;
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (has_geometry(*node.mChildren[i])) return true;
  return false;
}

// The root node is the file itself for OBJ (named after the file) and for a glTF scene with
// several root nodes ("ROOT"); a glTF scene with one root node becomes assimp's root, and that
// node is a node of the file.
bool root_is_a_file_node(const aiNode& root, MeshFormat format) {
  return format != MeshFormat::obj && root.mName.length > 0 &&
         std::string_view(root.mName.C_Str()) != "ROOT";
}

void list_nodes(const aiNode& node, bool include_this, std::vector<std::string>& names) {
  if (include_this && node.mName.length > 0 && has_geometry(node))
    names.emplace_back(node.mName.C_Str());
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    list_nodes(*node.mChildren[i], true, names);
}

const aiNode* find_node(const aiNode& node, std::string_view name) {
  if (std::string_view(node.mName.C_Str()) == name) return &node;
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (const aiNode* found = find_node(*node.mChildren[i], name)) return found;
  return nullptr;
}

// Appends the triangles of `node` and of the nodes below it, placed by `to_frame` (node → the
// chosen frame). Vertices at exactly the same position are joined, so a surface split by
// normals or texture seams becomes one closed surface again.
struct Collector {
  const aiScene& scene;
  geometry::TriangleMesh mesh;
  std::map<std::tuple<double, double, double>, std::uint32_t> index_of_position;

  void collect(const aiNode& node, const Eigen::Affine3d& to_frame) {
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
      const aiMesh& source = *scene.mMeshes[node.mMeshes[m]];
      if (!(source.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      std::vector<std::uint32_t> joined(source.mNumVertices);
      for (unsigned v = 0; v < source.mNumVertices; ++v) {
        const aiVector3D& p = source.mVertices[v];
        const geometry::Vec3 position = to_frame * geometry::Vec3(p.x, p.y, p.z);
        const auto key = std::make_tuple(position.x(), position.y(), position.z());
        const auto [it, inserted] =
            index_of_position.try_emplace(key, static_cast<std::uint32_t>(mesh.vertices.size()));
        if (inserted) mesh.vertices.push_back(position);
        joined[v] = it->second;
      }
      for (unsigned f = 0; f < source.mNumFaces; ++f) {
        const aiFace& face = source.mFaces[f];
        if (face.mNumIndices != 3) continue;
        mesh.triangles.push_back(
            {joined[face.mIndices[0]], joined[face.mIndices[1]], joined[face.mIndices[2]]});
      }
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i) {
      const aiNode& child = *node.mChildren[i];
      collect(child, to_frame * to_affine(child.mTransformation));
    }
  }
};

MeshImport convert(const aiScene* scene, const Assimp::Importer& importer, MeshFormat format,
                   std::optional<std::string_view> node) {
  MeshImport result;
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string why = importer.GetErrorString();
    result.error = "cannot read the " + std::string(to_string(format)) +
                   " file: " + (why.empty() ? std::string("the file is incomplete") : why);
    return result;
  }
  const aiNode& root = *scene->mRootNode;
  list_nodes(root, root_is_a_file_node(root, format), result.nodes);

  Collector collector{*scene, {}, {}};
  if (node) {
    const aiNode* chosen = find_node(root, *node);
    if (!chosen || (chosen == &root && !root_is_a_file_node(root, format))) {
      std::string names;
      for (const std::string& name : result.nodes)
        names += (names.empty() ? "'" : ", '") + name + "'";
      result.error = "the file has no node named '" + std::string(*node) + "'; " +
                     (names.empty() ? std::string("it has no named nodes with meshes")
                                    : "its nodes with meshes are " + names);
      return result;
    }
    collector.collect(*chosen, Eigen::Affine3d::Identity());
  } else {
    collector.collect(root, to_affine(root.mTransformation));
  }
  if (collector.mesh.triangles.empty()) {
    result.error = node ? "node '" + std::string(*node) + "' has no triangles"
                        : std::string("the file has no triangles");
    return result;
  }
  result.mesh = std::move(collector.mesh);
  return result;
}

}  // namespace

std::string_view to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::glb:
      return "glb";
    case MeshFormat::gltf:
      return "gltf";
    case MeshFormat::obj:
      return "obj";
  }
  return "glb";
}

std::optional<MeshFormat> parse_mesh_format(std::string_view name) {
  std::string lower(name);
  for (char& c : lower)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  if (lower == "glb") return MeshFormat::glb;
  if (lower == "gltf") return MeshFormat::gltf;
  if (lower == "obj") return MeshFormat::obj;
  return std::nullopt;
}

std::optional<MeshFormat> mesh_format_of_path(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension.size() < 2) return std::nullopt;
  return parse_mesh_format(std::string_view(extension).substr(1));
}

MeshImport import_mesh(std::string_view bytes, MeshFormat format,
                       std::optional<std::string_view> node) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  if (bytes.empty()) return {std::nullopt, {}, "the file is empty"};
  const std::string hint(to_string(format));
  const aiScene* scene =
      importer.ReadFileFromMemory(bytes.data(), bytes.size(), kImportFlags, hint.c_str());
  return convert(scene, importer, format, node);
}

MeshImport import_mesh_file(const std::filesystem::path& path,
                            std::optional<std::string_view> node) {
  const auto format = mesh_format_of_path(path);
  if (!format) {
    return {std::nullopt,
            {},
            "unknown mesh format '" + path.extension().string() + "'; use .glb, .gltf or .obj"};
  }
  std::error_code ignored;
  if (!std::filesystem::is_regular_file(path, ignored))
    return {std::nullopt, {}, "no such file: " + path.string()};
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(path.string(), kImportFlags);
  return convert(scene, importer, *format, node);
}

}  // namespace brisance::io
