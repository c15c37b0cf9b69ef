#include "dynamap/objects/object_options.h"

#include <ostream>

#include "dynamap/base/ini.h"
#include "dynamap/base/option_table.h"

namespace dynamap {

const OptionTable<ObjectOptions>& ObjectOptions::table() {
  using O = ObjectOptions;
  static const OptionTable<O> t(
      kSection,
      {
          {"enabled", &O::enabled, {}, "", "track objects at all"},
          {"join_distance", &O::join_distance, Range::closed(0.01, 2), "m",
           "object cells this close form one cluster"},
          {"min_cells", &O::min_cells, Range::closed(1, 1000), "", "fewer cells is not an object"},
          {"support_threshold", &O::support_threshold, Range::closedOpen(0, 1), "",
           "a cluster short of min_cells counts the D cells beside it above this P(occ) (0: off)"},
          {"min_size", &O::min_size, Range::closed(0, 20), "m",
           "smaller estimated sizes are noise"},
          {"max_size", &O::max_size, Range::openClosed(0, 20), "m",
           "larger clusters are not objects"},
          {"report_scans", &O::report_scans, Range::closed(1, 1000), "",
           "scans showing a new cluster's whole outline before it is reported, provisionally"},
          {"report_errors", &O::report_errors, Range::closed(0, 10), "",
           "...if its outlines' size names one object for any size within this many errors"},
          {"outline_jump", &O::outline_jump, Range::openClosed(0, 5), "m",
           "range step that ends an object's outline in a scan"},
          {"confirm_scans", &O::confirm_scans, Range::closed(1, 1000), "",
           "scans a reported cluster must last for its identity to be final"},
          {"settle_size", &O::settle_size, Range::closed(0, 1), "m",
           "...with its size changing no more than this from scan to scan"},
          {"wall_hug_distance", &O::wall_hug_distance, Range::closed(0, 1), "m",
           "D cells this close to S-occupied cells are wall noise"},
          {"thin_width", &O::thin_width, Range::closed(0, 1), "m",
           "a cluster this thin (std across its axis) near a wall is wall noise..."},
          {"thin_length", &O::thin_length, Range::closed(0, 20), "m", "...when at least this long"},
          {"size_tolerance", &O::size_tolerance, Range::openClosed(0, 5), "m",
           "identity by size: max size difference"},
          {"reappear_distance", &O::reappear_distance, Range::openClosed(0, 10), "m",
           "back this close to its last place: reappeared"},
          {"follow_margin", &O::follow_margin, Range::closed(0, 5), "m",
           "new cells within an object's radius + this continue it; a cluster there while it is "
           "seen is part of it"},
          {"move_distance", &O::move_distance, Range::openClosed(0, 10), "m",
           "drift that counts as a move"},
          {"defer_s", &O::defer_s, Range::closed(0, 1e6), "s",
           "max wait for an out-of-sight place to tell a move from a new object"},
          {"min_unseen_s", &O::min_unseen_s, Range::closed(0, 1e6), "s",
           "an object seen in place more recently did not move unseen"},
          {"min_rest_s", &O::min_rest_s, Range::closed(0, 1e6), "s",
           "a new object whose place is seen empty sooner after its report is retracted"},
          {"match_time_scale", &O::match_time_scale, Range::openClosed(0, 1e9), "s",
           "identity: cost of time since vanishing"},
          {"match_distance_scale", &O::match_distance_scale, Range::openClosed(0, 1e9), "m",
           "identity: cost of distance from the last place"},
          {"far_match_distance", &O::far_match_distance, Range::openClosed(0, 1e9), "m",
           "identity: a farther object matches only if no other has as near a size"},
          {"far_size_margin", &O::far_size_margin, Range::closed(0, 5), "m",
           "...nearer by at least this"},
          {"min_fit_cells", &O::min_fit_cells, Range::closed(3, 1000), "",
           "cells needed for a circle fit"},
      });
  return t;
}

void ObjectOptions::load(const IniFile& ini) {
  table().load(ini, *this);
  validate(ini.name());
}

void ObjectOptions::validate(const std::string& src) const {
  table().checkRanges(*this, src);
  if (!(min_size < max_size)) rejectValue(src, kSection, "min_size", "must be below max_size");
  if (report_scans > confirm_scans) {
    rejectValue(src, kSection, "report_scans", "must not exceed confirm_scans");
  }
}

void ObjectOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

}  // namespace dynamap
