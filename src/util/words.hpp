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

/// Byte offset of the first C0 control character (U+0000 to U+001F, tab and newline included) or
/// U+007F in `text`; npos when there is none.
size_t FirstControlCharacter(std::string_view text);

/// `text` with each byte that is not part of well-formed UTF-8 replaced by U+FFFD, as report.json
/// writes it: a path that is not UTF-8 (legal on Linux) in a text output (report.html, the
/// static transforms) leaves the output valid UTF-8.
std::string AsUtf8(std::string_view text);

/// `text` for a message: control characters written as \n, \t, \r, \0 or \xNN (U+007F as \x7F;
/// C1 controls and U+2028, U+2029 as \uNNNN),
/// so that a name never breaks the message's line (issue 15), and a backslash as \\ so that the
/// name's own backslashes never read as one of those escapes.
std::string Escaped(std::string_view text);

/// "" when `name` (a name, id or path read from an input file) has no control character (C0,
/// U+007F, C1) and no line or paragraph separator (U+2028, U+2029); else "has a control character
/// (U+000A) — use printable characters". Every reader checks its names
/// with it where they enter, as it checks UTF-8 (issue 15: a name with a newline broke
/// candidates.csv and the exported XML). Messages show the name through Escaped().
std::string NameProblem(std::string_view name);

/// Throws InputError "PATH:LINE: byte 0xE9 is not UTF-8 ..." unless `text`, the contents of the
/// scene file `path`, is UTF-8 (issue 15: a Latin-1 name reached report.json and ended in a JSON
/// type_error), or "PATH:LINE: byte 0x02 is a control character ..." when it holds a raw control
/// character other than tab, line feed and carriage return (YAML and XML allow no other).
/// Every scene reader (YAML, SDF, URDF) checks its files with it before parsing.
void CheckUtf8File(std::string_view text, const std::string& path);

/// The whole contents of the file at `path` into `bytes`, read in one piece at the file's size (a
/// file that grows meanwhile is still read to its end); false when it cannot be opened or a read
/// fails.
bool ReadWholeFile(const std::string& path, std::string* bytes);

/// The whole contents of an input file; InputError "PATH: cannot open the KIND — check the path"
/// (not a regular file) or "PATH: cannot read the KIND — check permissions". `kind` names it:
/// "scene file", "URDF file".
std::string ReadInputFile(const std::string& path, std::string_view kind);

}  // namespace vantage::detail
