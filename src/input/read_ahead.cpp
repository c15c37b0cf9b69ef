#include "dynamap/input/read_ahead.h"

#include <utility>

namespace dynamap {

ReadAheadSource::ReadAheadSource(std::unique_ptr<ScanSource> inner, std::size_t depth)
    : inner_(std::move(inner)),
      pose_source_(inner_->poseSource()),
      path_(inner_->path()),
      depth_(depth > 0 ? depth : 1) {
  reader_ = std::thread([this] { readLoop(); });
}

ReadAheadSource::~ReadAheadSource() {
  stop();
}

void ReadAheadSource::readLoop() {
  while (true) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_) return;
    }
    Item item;
    bool more = false;
    std::exception_ptr error;
    try {
      more = inner_->next(item.record);
      item.fraction = inner_->fractionRead();
    } catch (...) {
      error = std::current_exception();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    if (!more || error) {
      ended_ = true;
      error_ = error;
      changed_.notify_all();
      return;
    }
    // A full queue waits until next() has taken half of it: one wake-up per depth / 2 scans,
    // not one per scan.
    if (queue_.size() >= depth_) {
      reader_waiting_ = true;
      changed_.wait(lock, [this] { return queue_.size() <= depth_ / 2 || stopping_; });
      reader_waiting_ = false;
    }
    if (stopping_) return;
    queue_.push_back(std::move(item));
    if (taker_waiting_) changed_.notify_all();
  }
}

bool ReadAheadSource::next(ScanRecord& out) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (queue_.empty() && !ended_) {
    taker_waiting_ = true;
    changed_.wait(lock, [this] { return !queue_.empty() || ended_; });
    taker_waiting_ = false;
  }
  if (queue_.empty()) {
    // Every scan read before the end has been taken: now the end, or the error, is next.
    if (error_) std::rethrow_exception(error_);
    return false;
  }
  out = std::move(queue_.front().record);
  fraction_ = queue_.front().fraction;
  queue_.pop_front();
  if (reader_waiting_ && queue_.size() <= depth_ / 2) changed_.notify_all();
  return true;
}

void ReadAheadSource::stop() const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (reader_.joinable()) reader_.join();
  // Stopped early, the reader queues nothing more: next() must not wait for it.
  std::lock_guard<std::mutex> lock(mutex_);
  ended_ = true;
}

const SourceStats& ReadAheadSource::stats() const {
  stop();
  return inner_->stats();
}

std::string ReadAheadSource::poseDetail() const {
  stop();
  return inner_->poseDetail();
}

std::unique_ptr<ScanSource> readAhead(std::unique_ptr<ScanSource> inner) {
  return std::make_unique<ReadAheadSource>(std::move(inner));
}

}  // namespace dynamap
