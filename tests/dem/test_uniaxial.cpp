#include <gtest/gtest.h>
TEST(Uniaxial, Placeholder) {}
