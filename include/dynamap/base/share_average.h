#pragma once
// ShareAverage: a share in [0, 1] (of a scan's hits, say) averaged over about the last five
// scans, the latest weighing most: one scan of a crowd is no pose error, five in a row are.

namespace dynamap {

class ShareAverage {
 public:
  /// One more scan's share; the first one is the average.
  void add(double share) {
    value_ = have_ ? (1 - kWeight) * value_ + kWeight * share : share;
    have_ = true;
  }
  /// 0 before any scan.
  double value() const { return value_; }

 private:
  static constexpr double kWeight = 0.2;
  double value_ = 0;
  bool have_ = false;
};

}  // namespace dynamap
