#pragma once
/// Plain OBJ files read without Assimp's child process (issue 47: the bundled example's 11 kB OBJ
/// cost a fork and ~18 ms of Assimp in it). Only a form whose reading cannot differ from Assimp's
/// is taken; any other file goes to Assimp, which words its own refusals.
#include <optional>
#include <string>
#include <string_view>

#include "vantage/scene.hpp"

namespace vantage::detail {

/// A number as Assimp's OBJ reader reads it (fast_atof into a float: the integer part converted
/// from 64 bits, plus the first 15 fraction digits as an integer times 10^-digits in double,
/// rounded to float and added in float; the sign last). Only the plain form -?DIGITS[.DIGITS] is
/// taken (at most 18 integer digits); anything else (an exponent, a sign +, a leading or
/// trailing dot, nan, inf) gives nullopt.
std::optional<float> PlainObjNumber(std::string_view word);

/// The raw triangles of the `.obj` file at `path` when it holds only comment lines, at most one
/// `o NAME` line before the first face, `v x y z` lines and `f a b c` lines (three positive
/// indices among the vertices above), every word printable ASCII and every number plain
/// (PlainObjNumber): as Assimp's import gives them up to vantage's welding (the faces in file
/// order, each corner its own vertex, the float position plus Assimp's identity transform's
/// + 0). nullopt for any other file (and one without a face), which Assimp then reads.
std::optional<TriangleMesh> ReadPlainObj(const std::string& path);

}  // namespace vantage::detail
