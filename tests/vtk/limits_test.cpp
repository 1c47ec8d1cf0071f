// The VTK module's public headers cannot include the core, so vtkWireFurRenderPass.h repeats two
// of core/limits.h's limits in its clamp macros: they must stay the same values.
#include "vtkWireFurRenderPass.h"

#include "core/limits.h"

#include <vtkNew.h>

#include <gtest/gtest.h>

TEST(VtkLimits, RenderPassClampsAreTheCoreLimits)
{
  vtkNew<vtkWireFurRenderPass> pass;
  EXPECT_EQ(pass->GetBudgetMinValue(), 1);
  EXPECT_EQ(pass->GetBudgetMaxValue(), wf::kMaxListBudget);
  EXPECT_EQ(pass->GetThreadsMinValue(), 0);
  EXPECT_EQ(pass->GetThreadsMaxValue(), wf::kMaxThreads);
}
