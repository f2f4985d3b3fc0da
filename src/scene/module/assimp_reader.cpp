// The mesh reader module (issue 47): Assimp, loaded only in the child process that reads a mesh
// file with it (mesh.cpp ReadMeshFile), so that no other process maps Assimp and its libraries.
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <assimp/Importer.hpp>
#include <exception>
#include <string>

#include "vantage/scene.hpp"

namespace vantage {
namespace {

// What is wrong with the file, in the words mesh.cpp's FailMesh puts after "PATH: cannot read
// mesh: ".
struct Problem {
  std::string what;
};

[[noreturn]] void Fail(const std::string& what) { throw Problem{what}; }

/// What is wrong with `mesh`'s faces, "" when nothing: a face without vertices (Assimp's PLY
/// reader makes them of a file cut short, and its triangulation then asserts) or a vertex index
/// beyond the mesh's vertices (a broken PLY; reading it would read past them).
std::string FaceProblem(const aiMesh& mesh) {
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices == 0) return fmt::format("face {} has no vertices (a file cut short?)", f);
    for (unsigned k = 0; k < face.mNumIndices; ++k) {
      if (face.mIndices[k] < mesh.mNumVertices) continue;
      return fmt::format("face {} refers to vertex index {}, out of range: the mesh has {} "
                         "vertices (indices 0 to {})",
                         f, face.mIndices[k], mesh.mNumVertices,
                         static_cast<int64_t>(mesh.mNumVertices) - 1);
    }
  }
  return {};
}

/// Appends the triangles of one Assimp mesh, placed by `world_from_mesh`; lines and points
/// (left by aiProcess_SortByPType) are skipped. A face problem (FaceProblem) sets `problem`.
void AppendAssimpMesh(const aiMesh& mesh, const aiMatrix4x4& world_from_mesh, TriangleMesh* out,
                      std::string* problem) {
  if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !problem->empty()) return;
  *problem = FaceProblem(mesh);
  if (!problem->empty()) return;
  const auto base = static_cast<uint32_t>(out->vertices.size());
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D p = world_from_mesh * mesh.mVertices[v];
    out->vertices.emplace_back(p.x, p.y, p.z);
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    out->triangles.push_back(
        {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
  }
}

/// Walks the node tree, composing each node's transform onto its parent's.
void Flatten(const aiScene& scene,
             const aiNode& node,
             const aiMatrix4x4& parent,
             TriangleMesh* out,
             std::string* problem) {
  const aiMatrix4x4 world_from_node = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] < scene.mNumMeshes)
      AppendAssimpMesh(*scene.mMeshes[node.mMeshes[i]], world_from_node, out, problem);
  }
  for (unsigned i = 0; i < node.mNumChildren; ++i) {
    Flatten(scene, *node.mChildren[i], world_from_node, out, problem);
  }
}

/// Assimp's import of `path` (PlyBodyProblem already checked) into `raw`, or Problem.
void ImportWithAssimp(const std::string& path, TriangleMesh* raw) {
  Assimp::Importer importer;
  // Gazebo uses a Collada file's coordinates as they are (Z up in practice), with only the
  // <unit> scale applied; Assimp would otherwise rotate Z_UP files to Y up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode) Fail(importer.GetErrorString());
  // Checked before Assimp's triangulation, which asserts (Debian's build aborts) on a face
  // without vertices, as its PLY reader made of a file cut short (session 9).
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    if (const std::string problem = FaceProblem(*scene->mMeshes[m]); !problem.empty())
      Fail(problem);
  }
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) Fail(importer.GetErrorString());
  std::string problem;
  Flatten(*scene, *scene->mRootNode, aiMatrix4x4(), raw, &problem);
  if (!problem.empty()) Fail(problem);
}

}  // namespace
}  // namespace vantage

/// The module's one entry (MeshModuleEntry in mesh.cpp): the raw triangles of the mesh file at
/// `path` in `*raw`, and 0; 1 and what is wrong with the file in `*problem`; 2 and the message of
/// any other failure. Throws nothing.
extern "C" __attribute__((visibility("default"))) int vantage_read_mesh(const char* path,
                                                                      vantage::TriangleMesh* raw,
                                                                      std::string* problem) {
  try {
    vantage::ImportWithAssimp(path, raw);
    return 0;
  } catch (const vantage::Problem& p) {
    *problem = p.what;
    return 1;
  } catch (const std::exception& e) {
    *problem = e.what();
  } catch (...) {
    *problem = "Assimp failed";
  }
  return 2;
}
