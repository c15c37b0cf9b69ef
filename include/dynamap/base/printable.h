#pragma once
// Text from files (a line type, a class name, a path) on its way to a terminal: a message must
// not carry the file's escape sequences or bytes a terminal cannot show.

#include <string>

namespace dynamap {

/// `s` with every control byte (ESC, NUL, ...; tab and newline kept) and every byte that is not
/// part of valid UTF-8 written as \xNN; valid UTF-8 text is unchanged.
std::string printable(const std::string& s);

}  // namespace dynamap
