#pragma once
/// What the readers tell OutputGuard (vantage/output_guard.hpp).
#include <string>
#include <string_view>

namespace vantage::detail {

/// Every reader calls this with each file it is about to open (`kind`: "mesh file", "URDF
/// file", ...). InputError naming the option when a live OutputGuard will write that file.
void NoteInputFile(const std::string& path, std::string_view kind);

}  // namespace vantage::detail
