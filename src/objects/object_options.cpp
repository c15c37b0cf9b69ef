#include "dynamap/objects/object_options.h"

#include <iomanip>
#include <ostream>

#include "dynamap/base/ini.h"

namespace dynamap {

namespace {

[[noreturn]] void reject(const std::string& source, const char* key, const std::string& why) {
  rejectValue(source, ObjectOptions::kSection, key, why);
}

void requireRange(const std::string& src, const char* key, double v, double lo, double hi,
                  const char* text) {
  requireInRange(src, ObjectOptions::kSection, key, v, lo, hi, text);
}

}  // namespace

void ObjectOptions::load(const IniFile& ini) {
  const std::string s = kSection;
  ini.requireKnownKeys(
      s, {"enabled", "join_distance", "min_cells", "min_size", "max_size", "confirm_scans",
          "settle_size", "wall_hug_distance", "thin_width", "thin_length", "size_tolerance",
          "reappear_distance", "follow_margin", "move_distance", "defer_s", "min_unseen_s",
          "match_time_scale", "match_distance_scale", "min_fit_cells"});
  enabled = ini.getBool(s, "enabled", enabled);
  join_distance = ini.getDouble(s, "join_distance", join_distance);
  min_cells = static_cast<int>(ini.getInt(s, "min_cells", min_cells));
  min_size = ini.getDouble(s, "min_size", min_size);
  max_size = ini.getDouble(s, "max_size", max_size);
  confirm_scans = static_cast<int>(ini.getInt(s, "confirm_scans", confirm_scans));
  settle_size = ini.getDouble(s, "settle_size", settle_size);
  wall_hug_distance = ini.getDouble(s, "wall_hug_distance", wall_hug_distance);
  thin_width = ini.getDouble(s, "thin_width", thin_width);
  thin_length = ini.getDouble(s, "thin_length", thin_length);
  size_tolerance = ini.getDouble(s, "size_tolerance", size_tolerance);
  reappear_distance = ini.getDouble(s, "reappear_distance", reappear_distance);
  follow_margin = ini.getDouble(s, "follow_margin", follow_margin);
  move_distance = ini.getDouble(s, "move_distance", move_distance);
  defer_s = ini.getDouble(s, "defer_s", defer_s);
  min_unseen_s = ini.getDouble(s, "min_unseen_s", min_unseen_s);
  match_time_scale = ini.getDouble(s, "match_time_scale", match_time_scale);
  match_distance_scale = ini.getDouble(s, "match_distance_scale", match_distance_scale);
  min_fit_cells = static_cast<int>(ini.getInt(s, "min_fit_cells", min_fit_cells));
  validate(ini.name());
}

void ObjectOptions::validate(const std::string& src) const {
  requireRange(src, "join_distance", join_distance, 0.01, 2.0, "in [0.01, 2] m");
  requireRange(src, "min_cells", min_cells, 1, 1000, "in [1, 1000]");
  requireRange(src, "max_size", max_size, 0.0, 20.0, "in (0, 20] m");
  if (!(max_size > 0.0)) reject(src, "max_size", "must be > 0 m");
  requireRange(src, "min_size", min_size, 0.0, 20.0, "in [0, max_size) m");
  if (!(min_size < max_size)) reject(src, "min_size", "must be below max_size");
  requireRange(src, "confirm_scans", confirm_scans, 1, 1000, "in [1, 1000]");
  requireRange(src, "settle_size", settle_size, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "wall_hug_distance", wall_hug_distance, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "thin_width", thin_width, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "thin_length", thin_length, 0.0, 20.0, "in [0, 20] m");
  requireRange(src, "size_tolerance", size_tolerance, 1e-9, 5.0, "in (0, 5] m");
  requireRange(src, "reappear_distance", reappear_distance, 1e-9, 10.0, "in (0, 10] m");
  requireRange(src, "follow_margin", follow_margin, 0.0, 5.0, "in [0, 5] m");
  requireRange(src, "move_distance", move_distance, 1e-9, 10.0, "in (0, 10] m");
  requireRange(src, "defer_s", defer_s, 0.0, 1e6, "in [0, 1e6] s");
  requireRange(src, "min_unseen_s", min_unseen_s, 0.0, 1e6, "in [0, 1e6] s");
  requireRange(src, "match_time_scale", match_time_scale, 1e-9, 1e9, "> 0 s");
  requireRange(src, "match_distance_scale", match_distance_scale, 1e-9, 1e9, "> 0 m");
  requireRange(src, "min_fit_cells", min_fit_cells, 3, 1000, "in [3, 1000]");
}

void ObjectOptions::writeIni(std::ostream& out) const {
  out << std::setprecision(10);
  out << "[" << kSection << "]\n"
      << "enabled = " << (enabled ? "true" : "false") << " ; track objects at all\n"
      << "join_distance = " << join_distance << " ; [m] object cells this close form one cluster\n"
      << "min_cells = " << min_cells << " ; fewer cells is not an object\n"
      << "min_size = " << min_size << " ; [m] smaller estimated sizes are noise\n"
      << "max_size = " << max_size << " ; [m] larger clusters are not objects\n"
      << "confirm_scans = " << confirm_scans << " ; scans a new cluster must last to be reported\n"
      << "settle_size = " << settle_size
      << " ; [m] ...with its size changing no more than this from scan to scan\n"
      << "wall_hug_distance = " << wall_hug_distance
      << " ; [m] D cells this close to S-occupied cells are wall noise\n"
      << "thin_width = " << thin_width
      << " ; [m] a cluster this thin (std across its axis) near a wall is wall noise...\n"
      << "thin_length = " << thin_length << " ; [m] ...when at least this long\n"
      << "size_tolerance = " << size_tolerance << " ; [m] identity by size: max size difference\n"
      << "reappear_distance = " << reappear_distance
      << " ; [m] back this close to its last place: reappeared\n"
      << "follow_margin = " << follow_margin
      << " ; [m] new cells within an object's radius + this continue it\n"
      << "move_distance = " << move_distance << " ; [m] drift that counts as a move\n"
      << "defer_s = " << defer_s
      << " ; [s] max wait for an out-of-sight place to tell a move from a new object\n"
      << "min_unseen_s = " << min_unseen_s
      << " ; [s] an object seen in place more recently did not move unseen\n"
      << "match_time_scale = " << match_time_scale
      << " ; [s] identity: cost of time since vanishing\n"
      << "match_distance_scale = " << match_distance_scale
      << " ; [m] identity: cost of distance from the last place\n"
      << "min_fit_cells = " << min_fit_cells << " ; cells needed for a circle fit\n";
}

}  // namespace dynamap
