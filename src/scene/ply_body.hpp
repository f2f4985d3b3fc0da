#pragma once
/// Whether a PLY file holds every element its header declares. Assimp's PLY reader fills what a
/// file cut short lacks with the last values read (repeated faces, or faces without vertices on
/// which its triangulation asserts and aborts, session 9), so the body is walked first.
#include <string>

namespace vantage::detail {

/// "" when `path` is no PLY file (Assimp then reads it) or when its header is well formed and its
/// body holds every declared element; else what is wrong, e.g. "it ends inside element 'face'
/// 4 of 4 declared in its header (a file cut short?)" or "header line 4: 'propelement' is no PLY
/// header keyword (...)". Assimp's PLY reader crashed or looped on such files.
std::string PlyBodyProblem(const std::string& path);

}  // namespace vantage::detail
