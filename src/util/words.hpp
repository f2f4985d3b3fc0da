#pragma once
/// Words in messages: "did you mean" suggestions and quoted lists (STYLE.md: errors say how to fix).
#include <string>
#include <string_view>
#include <vector>

#include "vantage/words.hpp"

namespace vantage::detail {

using vantage::ClosestWord;
using vantage::EditDistance;

/// 'a', 'b', 'c'
std::string JoinQuoted(const std::vector<std::string>& words);

/// Byte offset of the first byte of `text` that is not part of well-formed UTF-8 (RFC 3629: no
/// overlong forms, surrogates or code points above U+10FFFF); npos when all of it is.
size_t FirstNonUtf8Byte(std::string_view text);

/// Throws InputError "PATH:LINE: byte 0xE9 is not UTF-8 ..." unless `text`, the contents of the
/// scene file `path`, is UTF-8 (issue 15: a Latin-1 name reached report.json and ended in a JSON
/// type_error). Both scene readers check their files with it before parsing.
void CheckUtf8File(std::string_view text, const std::string& path);

/// The whole contents of an input file; InputError "PATH: cannot open the KIND — check the path"
/// (not a regular file) or "PATH: cannot read the KIND — check permissions". `kind` names it:
/// "scene file", "URDF file".
std::string ReadInputFile(const std::string& path, std::string_view kind);

}  // namespace vantage::detail
