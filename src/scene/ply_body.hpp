#pragma once
/// Whether a PLY file holds every element its header declares. Assimp's PLY reader fills what a
/// file cut short lacks with the last values read (repeated faces, or faces without vertices on
/// which its triangulation asserts and aborts, session 9), so the body is walked first.
#include <string>

namespace vantage::detail {

/// "" when `path` is no PLY file this walker understands (Assimp then reports it) or when its
/// body holds every declared element; else what is missing, e.g. "it ends inside element 'face'
/// 4 of 4 declared in its header (a file cut short?)".
std::string PlyBodyProblem(const std::string& path);

}  // namespace vantage::detail
