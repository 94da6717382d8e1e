// The grid field as the exact integral sees it: node and cell layouts, trilinear and nearest
// interpolation (their cell planes and half-way planes are the breaks the reference integrates
// between), checked ray by ray against the independent long-double integral (reference_check.h).
#include "lib/grid_field.h"

#include <gtest/gtest.h>

#include "tests/lib/reference_check.h"

namespace vrv {
namespace {

using namespace reference_check;

TEST(ReferenceIntegratorGrid, NodeTrilinear) {
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  check_rays("grid 9^3 node trilinear (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 21));
}

TEST(ReferenceIntegratorGrid, CellTrilinear) {
  const GridField grid = make_grid(kBox, kML, {8, 8, 8}, GridLayout::cell, Interpolation::trilinear);
  check_rays("grid 8^3 cell trilinear (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 22));
}

TEST(ReferenceIntegratorGrid, NodeNearest) {
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::nearest);
  check_rays("grid 9^3 node nearest (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 23));
}

}  // namespace
}  // namespace vrv
