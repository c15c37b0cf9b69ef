#include "dynamap/outputs/tables.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>

#include "dynamap/base/csv_schema.h"
#include "dynamap/outputs/format.h"
#include "dynamap/outputs/map_outputs.h"

namespace dynamap {

StreamedFile::StreamedFile(const std::string& dir, const std::string& name,
                           const std::string& header)
    : dir_(dir), name_(name), tmp_(tempName(dir, name)) {
  out_ = std::make_unique<std::ofstream>(tmp_, std::ios::binary | std::ios::trunc);
  if (!*out_) {
    throw std::runtime_error(dir + "/" + name + ": cannot write (" + std::strerror(errno) + ")");
  }
  *out_ << header;
}

StreamedFile::~StreamedFile() {
  if (!out_) return;
  out_.reset();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);  // not finished: leave no half-written file
}

void StreamedFile::finish() {
  out_->flush();
  const bool ok = static_cast<bool>(*out_);
  const int err = errno;  // ENOSPC on a full disk
  out_.reset();
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
    throw std::runtime_error(dir_ + "/" + name_ + ": write failed (" + std::strerror(err) + ")");
  }
  commit(tmp_, dir_, name_);
}

PeopleLog::PeopleLog(const std::string& dir)
    : file_(dir, "people.csv", std::string(csv::kPeople) + "\n") {}

void PeopleLog::append(std::size_t scan_index, double t, const PersonTracker& people) {
  for (const PersonRow& p : people.reported()) {
    file_.out() << scan_index << ',' << fmt("%.6f", t) << ',' << p.person_id << ','
                << fmt("%.3f", p.x) << ',' << fmt("%.3f", p.y) << ',' << fmt("%.3f", p.vx) << ','
                << fmt("%.3f", p.vy) << '\n';
  }
}

TrackLog::TrackLog(const std::string& dir)
    : file_(dir, "tracks.csv", std::string(csv::kTracks) + "\n") {}

void TrackLog::append(std::size_t scan_index, double t, const ObjectTracker& tracker) {
  // Every present object every scan: the rows are built in one reused buffer, one write a scan.
  rows_.clear();
  for (const TrackedObject& o : tracker.objects()) {
    if (o.state != ObjectState::Present) continue;
    const ShapeEstimate& s = o.shape;
    appendInt(rows_, scan_index);
    rows_ += ',';
    appendFixed(rows_, t, 6);
    rows_ += ',';
    appendInt(rows_, o.id);
    for (const double v : {s.cx, s.cy, s.size, s.x_min, s.x_max, s.y_min, s.y_max}) {
      rows_ += ',';
      appendFixed(rows_, v, 3);
    }
    rows_ += '\n';
  }
  file_.out() << rows_;
}

PoseLog::PoseLog(const std::string& dir)
    : file_(dir, "poses.txt", "% timestamp x y phi (the pose each scan was mapped at)\n") {}

void PoseLog::append(double t, const mrpt::poses::CPose2D& pose) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f\n", t, pose.x(), pose.y(), pose.phi());
  file_.out() << buf;
}

bool eventsListed(const ObjectTracker& tracker, int id) {
  return tracker.objects()[static_cast<std::size_t>(id - 1)].state != ObjectState::Withdrawn;
}

void writeObjectsCsv(std::ostream& o, const ObjectTracker& tracker) {
  o << csv::kObjects << "\n";
  for (const TrackedObject& ob : tracker.objects()) {
    if (!listedInTable(ob.state)) continue;
    const ShapeEstimate& s = ob.shape;
    o << ob.id << ',' << ob.label << ',' << fmt("%.3f", s.size) << ',' << fmt("%.3f", s.cx) << ','
      << fmt("%.3f", s.cy) << ',' << fmt("%.3f", s.x_min) << ',' << fmt("%.3f", s.x_max) << ','
      << fmt("%.3f", s.y_min) << ',' << fmt("%.3f", s.y_max) << ',' << toString(ob.state) << ','
      << fmt("%.6f", ob.first_seen_t) << ',' << fmt("%.6f", ob.last_seen_t) << ',' << ob.n_moves
      << '\n';
  }
}

void writeEventsCsv(std::ostream& o, const ObjectTracker& tracker) {
  o << "t,scan_index,object_id,event,cx,cy,size_m,from_id\n";
  for (const EventRecord& e : tracker.events()) {
    if (!eventsListed(tracker, e.object_id)) continue;
    o << fmt("%.6f", e.t) << ',' << e.scan_index << ',' << e.object_id << ',' << toString(e.event)
      << ',' << fmt("%.3f", e.cx) << ',' << fmt("%.3f", e.cy) << ',' << fmt("%.3f", e.size) << ',';
    if (e.from_id) o << e.from_id;
    o << '\n';
  }
}

void writeChangesCsv(std::ostream& o, const std::vector<ChangeRow>& rows) {
  o << csv::kChanges << "\n";
  const auto num = [](const char* f, double v) { return std::isnan(v) ? std::string() : fmt(f, v); };
  for (const ChangeRow& r : rows) {
    o << r.kind << ',' << r.id << ',' << fmt("%.3f", r.size) << ',' << num("%.3f", r.from_x) << ','
      << num("%.3f", r.from_y) << ',' << num("%.3f", r.to_x) << ',' << num("%.3f", r.to_y) << ','
      << num("%.6f", r.first_seen_t) << ',' << r.cells << '\n';
  }
}

}  // namespace dynamap
