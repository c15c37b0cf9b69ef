#pragma once
// JSON outputs (summary.json, metrics.json) built and written with nlohmann-json, keys in the
// order written. Text from files (a log's path, a fault naming a line type read from it) may
// hold any bytes: dump() replaces what is not UTF-8 with U+FFFD and escapes control characters,
// so the file is always valid JSON.

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>

namespace dynamap {

using Json = nlohmann::ordered_json;

/// `v` as the printf `format` ("%.3f", "%.6g") prints it, as a JSON number of exactly that
/// decimal value: an integer when the text has no fraction or exponent. Outputs then hold the
/// digits a fixed format gives (byte-identical between runs), not a double's 17.
Json jsonNumber(const char* format, double v);
/// `j` indented by two spaces, invalid UTF-8 replaced, and a final newline.
void writeJson(std::ostream& out, const Json& j);
/// The JSON text of a file; throws std::runtime_error naming `path` when it is not JSON.
Json parseJson(const std::string& text, const std::string& path);

}  // namespace dynamap
