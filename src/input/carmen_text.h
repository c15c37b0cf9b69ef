#pragma once
// How the CARMEN reader writes numbers into its messages; shared by the parser
// (carmen_parse.cpp) and the streaming reader (carmen_reader.cpp). Private to them.

#include <string>

namespace dynamap::carmen {

/// An angle in degrees as a message shows it: at most 3 decimals, no trailing zeros.
std::string formatDeg(double deg);

}  // namespace dynamap::carmen
