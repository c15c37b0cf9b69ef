#include "dynamap/outputs/json.h"

#include <cmath>
#include <ostream>
#include <stdexcept>

#include "dynamap/outputs/format.h"

namespace dynamap {

Json jsonNumber(const char* format, double v) {
  if (!std::isfinite(v)) return nullptr;  // JSON has no NaN or infinity
  const std::string text = fmt(format, v);
  if (text.find_first_of(".eE") == std::string::npos) return Json(std::stoll(text));
  return Json(std::stod(text));
}

void writeJson(std::ostream& out, const Json& j) {
  out << j.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
}

Json parseJson(const std::string& text, const std::string& path) {
  Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw std::runtime_error(path + ": not valid JSON");
  return j;
}

}  // namespace dynamap
