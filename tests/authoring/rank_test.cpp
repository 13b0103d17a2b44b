#include "annex/authoring/rank.h"

#include <gtest/gtest.h>

namespace annex::authoring {
namespace {

TEST(RankWeights, LinearStepsFromOneDown) {
  const std::vector<double> w = rank_weights(3);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_DOUBLE_EQ(w[0], 1.0);
  EXPECT_DOUBLE_EQ(w[1], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(w[2], 1.0 / 3.0);
  EXPECT_EQ(rank_weights(1), std::vector<double>{1.0});
  EXPECT_TRUE(rank_weights(0).empty());
}

TEST(RankWeights, OrderByWeightKeepsAuthoredOrderOnTies) {
  EXPECT_EQ(order_by_weight({0.5, 1.0, 0.5, 0.9}), (std::vector<int>{1, 3, 0, 2}));
}

TEST(RankWeights, WeightsFollowOrderAndRoundTrip) {
  const std::vector<int> order{2, 0, 1};
  const std::vector<double> w = weights_from_order(order);
  EXPECT_DOUBLE_EQ(w[2], 1.0);
  EXPECT_DOUBLE_EQ(w[0], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(w[1], 1.0 / 3.0);
  EXPECT_EQ(order_by_weight(w), order);
}

TEST(RankWeights, PermutationCheck) {
  EXPECT_TRUE(is_permutation_of_n({1, 0, 2}, 3));
  EXPECT_FALSE(is_permutation_of_n({1, 1, 2}, 3));
  EXPECT_FALSE(is_permutation_of_n({0, 1}, 3));
  EXPECT_FALSE(is_permutation_of_n({0, 3, 1}, 3));
}

}  // namespace
}  // namespace annex::authoring
