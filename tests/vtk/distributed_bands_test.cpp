// The sort-first split of the WireFur render pass under MPI (vtk_filters/wf_render_pass_distributed.h,
// bandOf): the bands cover the image's rows once, in rank order, each made of whole rows of the
// core's tiles, so that no tile is rasterised (and its fragments counted) by two ranks; the work
// is shared evenly (the band sizes differ by at most one row of tiles).
#include "render/renderer.h"
#include "wf_render_pass_distributed.h"

#include <gtest/gtest.h>

#include <algorithm>

TEST(DistributedBands, WholeRowsOfTilesCoveringTheImageOnce) {
  for (int ranks = 1; ranks <= 17; ++ranks)
    for (int h = 1; h <= 1100; h += (h < 100 ? 1 : 37)) {
      int next = 0, smallest = h, largest = 0;
      for (int r = 0; r < ranks; ++r) {
        int b0 = -1, b1 = -1;
        wfvtk::bandOf(r, ranks, h, b0, b1);
        ASSERT_EQ(b0, next) << "h " << h << " ranks " << ranks << " rank " << r;
        ASSERT_LE(b0, b1);
        if (b0 < h) {
          EXPECT_EQ(b0 % wfvtk::kBandRows, 0);  // (an empty band at the end starts at h)
        }
        if (b1 < h) {
          EXPECT_EQ(b1 % wfvtk::kBandRows, 0);
        }
        next = b1;
        const int tiles = (b1 - b0 + wfvtk::kBandRows - 1) / wfvtk::kBandRows;
        smallest = std::min(smallest, tiles), largest = std::max(largest, tiles);
      }
      EXPECT_EQ(next, h) << "h " << h << " ranks " << ranks;
      EXPECT_LE(largest - smallest, 1) << "h " << h << " ranks " << ranks;
    }
}

TEST(DistributedBands, TheCoresDefaultTileSize) {
  EXPECT_EQ(wf::RenderOptions{}.tileSize, wfvtk::kBandRows);
}
