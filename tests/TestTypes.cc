// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Types.h>

#include <openvdb/Exceptions.h>

#include <gtest/gtest.h>

class TestTypes : public ::testing::Test {};

TEST_F(TestTypes, testDefaultPriorityIsNumeric)
{
    vdbi::LabelPriority p;
    EXPECT_TRUE(p.higher(-3, 0));
    EXPECT_TRUE(p.higher(0, 7));
    EXPECT_EQ(p.pick(9, 4), 4);
}

TEST_F(TestTypes, testUserPriorityComesFirst)
{
    vdbi::LabelPriority p({7, 2});
    EXPECT_TRUE(p.higher(7, 2));
    EXPECT_TRUE(p.higher(2, 0));
    EXPECT_TRUE(p.higher(0, 5));
    EXPECT_EQ(p.pick(0, 7), 7);
    EXPECT_THROW(vdbi::LabelPriority({1, 2, 1}), openvdb::ValueError);
}
