// Identity by size, helped by position and time.

#include "dynamap/objects/identity.h"

#include <gtest/gtest.h>

namespace dynamap {
namespace {

ShapeEstimate detection(double x, double y, double size) {
  ShapeEstimate s;
  s.cx = x;
  s.cy = y;
  s.size = size;
  return s;
}

TEST(ChooseIdentity, TwoSimilarSizesTheAbsentOneIsTheOneThatMoved) {
  ObjectOptions o;
  // A (0.30) was seen gone; B (0.32) is seen where it was: the 0.31 detection is A.
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.32, false, 0.0, PlaceView::SeenOccupied},
      {5.0, 5.0, 0.30, true, 90.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, c, o), 1);
  // Same sizes, roles swapped.
  const std::vector<IdentityCandidate> d{
      {0.0, 0.0, 0.32, true, 90.0, PlaceView::NotInView},
      {5.0, 5.0, 0.30, false, 0.0, PlaceView::SeenOccupied},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, d, o), 0);
}

TEST(ChooseIdentity, TwoSimilarSizesBothAbsentTheRecentAndNearOneWins) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {-6.0, 0.0, 0.30, true, 10.0, PlaceView::NotInView},  // gone long ago, far
      {2.5, 2.0, 0.31, true, 98.0, PlaceView::NotInView},   // just gone, near
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), 1);
}

TEST(ChooseIdentity, PresentObjectSeenInPlaceOrOtherSizeMeansNew) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.30, false, 0.0, PlaceView::SeenOccupied},
      {3.0, 0.0, 0.60, true, 10.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), -1);
}

TEST(ChooseIdentity, PresentObjectOutOfSightMayHaveMoved) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.30, false, 0.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), 0);
}

TEST(ChooseIdentity, FarMatchOnlyForASizeNoOtherObjectShares) {
  ObjectOptions o;
  o.far_match_distance = 10.0;
  // An absent 0.30 m object 15 m away: taken while its size is its own...
  std::vector<IdentityCandidate> c{{17.0, 2.0, 0.30, true, 90.0, PlaceView::NotInView}};
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, c, o), 0);
  // ...not once another known object is of that size too: a new object.
  c[0].shared_size = true;
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, c, o), -1);
  // Within far_match_distance a shared size still matches, by cost as before.
  c[0].cx = 9.0;
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, c, o), 0);
}

}  // namespace
}  // namespace dynamap
