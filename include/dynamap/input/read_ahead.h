#pragma once
// ReadAheadSource: another source read on a thread of its own, a bounded number of scans ahead.
//
// Reading a log (inflating gzip, parsing text, decoding MRPT's records) is a fifth to a third of
// a run and depends on nothing the mapping computes, so on a machine with a second core it can
// be done beside the mapping. The scans, their order, their poses and every error come out
// exactly as from the inner source: an error is thrown by next() where the inner source threw
// it, after every scan read before it. Memory is bounded by `depth` scans.

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "dynamap/input/scan_source.h"

namespace dynamap {

class ReadAheadSource : public ScanSource {
 public:
  /// Starts reading `inner` at once, at most `depth` scans ahead of next().
  explicit ReadAheadSource(std::unique_ptr<ScanSource> inner, std::size_t depth = 64);
  /// Stops the reader (it finishes the record it is on) and waits for it.
  ~ReadAheadSource() override;
  ReadAheadSource(const ReadAheadSource&) = delete;
  ReadAheadSource& operator=(const ReadAheadSource&) = delete;

  bool next(ScanRecord& out) override;
  PoseSource poseSource() const override { return pose_source_; }
  const std::string& path() const override { return path_; }
  /// The inner source's fraction when it had read the scan next() returned last.
  double fractionRead() const override { return fraction_; }
  /// stats() and poseDetail() stop the reader first (they are the inner source's, which the
  /// reader changes): call them once next() has returned false or thrown, as a run does. Called
  /// earlier, next() then gives the scans already queued and returns false.
  const SourceStats& stats() const override;
  std::string poseDetail() const override;

 private:
  struct Item {
    ScanRecord record;
    double fraction = -1.0;
  };
  void readLoop();
  void stop() const;

  std::unique_ptr<ScanSource> inner_;
  const PoseSource pose_source_;
  const std::string path_;
  const std::size_t depth_;
  double fraction_ = -1.0;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::deque<Item> queue_;         // read, not yet taken
  mutable bool ended_ = false;     // the reader is done: queue_ is all there is
  std::exception_ptr error_;       // what ended it, if the inner source threw
  mutable bool stopping_ = false;  // asked to stop early
  bool reader_waiting_ = false;    // the reader waits for room
  bool taker_waiting_ = false;     // next() waits for a scan
  mutable std::thread reader_;
};

/// `inner` read ahead on a thread of its own (ReadAheadSource).
std::unique_ptr<ScanSource> readAhead(std::unique_ptr<ScanSource> inner);

}  // namespace dynamap
