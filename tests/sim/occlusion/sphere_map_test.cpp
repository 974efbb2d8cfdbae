// Tests for sim/occlusion/sphere_map: the icosahedral pixelisation of directions.
#include "sim/occlusion/sphere_map.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace brisance::occlusion {
namespace {

Vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

TEST(SphereMap, EveryPixelCentreMapsBackToItselfAwayFromFaceEdges) {
  const SphereMap map(32, 28);
  EXPECT_EQ(map.pixel_count() % 20, 0u);
  int self = 0;
  for (std::uint32_t p = 0; p < map.pixel_count(); ++p)
    self += map.pixel_of(map.pixel_direction(p)) == p;
  // Cells straddling a face edge have their centre outside the face, where the neighbouring face
  // owns the direction; every other cell maps to itself.
  EXPECT_GT(self, static_cast<int>(map.pixel_count() * 8 / 10));
}

TEST(SphereMap, EveryDirectionLandsInANearbyPixel) {
  const SphereMap map(32, 28);
  // A reference pixel spans about 63.4 deg / 32 = 2 deg of arc; its centre is within ~1.5 px.
  const double pixel_arc = 2.0 * std::asin(map.edge_length() / 2.0) / map.columns();
  std::mt19937_64 rng(5);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 d = random_direction(rng);
    const double apart =
        std::acos(std::clamp(d.dot(map.pixel_direction(map.pixel_of(d))), -1.0, 1.0));
    ASSERT_LT(apart, 1.5 * pixel_arc) << "direction " << d.transpose();
  }
}

TEST(SphereMap, PixelsCoverTheSphereAboutEvenly) {
  const SphereMap map(16, 14);
  std::vector<int> hits(map.pixel_count(), 0);
  std::mt19937_64 rng(9);
  const int samples = 400000;
  for (int i = 0; i < samples; ++i)
    ++hits[map.pixel_of(random_direction(rng))];
  // Cells cut by a face edge hold only the sliver of the face inside them, and a few slivers are
  // too thin to be hit at this sample count; every other cell is reached, and the typical cell
  // holds its share.
  int empty = 0;
  for (int h : hits)
    empty += h == 0;
  EXPECT_LT(empty, static_cast<int>(map.pixel_count() / 100));
  std::vector<int> sorted(hits);
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  EXPECT_NEAR(median, static_cast<double>(samples) / map.pixel_count(),
              0.5 * samples / map.pixel_count());
}

TEST(SphereMap, NeighboursAreSymmetricAdjacentAndCrossFaceEdges) {
  const SphereMap map(32, 28);
  const double pixel_arc = 2.0 * std::asin(map.edge_length() / 2.0) / map.columns();
  std::set<int> faces_linked;
  for (std::uint32_t p = 0; p < map.pixel_count(); ++p) {
    const auto around = map.neighbours(p);
    ASSERT_GE(around.size(), 2u);
    for (std::uint32_t q : around) {
      const auto back = map.neighbours(q);
      EXPECT_NE(std::find(back.begin(), back.end(), p), back.end());
      const double apart =
          std::acos(std::clamp(map.pixel_direction(p).dot(map.pixel_direction(q)), -1.0, 1.0));
      EXPECT_LT(apart, 2.5 * pixel_arc);
    }
  }
  // Walking neighbours from one pixel reaches the whole sphere: the seams are stitched.
  std::vector<bool> seen(map.pixel_count(), false);
  std::vector<std::uint32_t> queue = {0};
  seen[0] = true;
  for (std::size_t h = 0; h < queue.size(); ++h) {
    for (std::uint32_t q : map.neighbours(queue[h])) {
      if (!seen[q]) {
        seen[q] = true;
        queue.push_back(q);
      }
    }
  }
  EXPECT_EQ(queue.size(), map.pixel_count());
}

}  // namespace
}  // namespace brisance::occlusion
