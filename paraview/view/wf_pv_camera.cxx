#include "wf_pv_camera.h"

#include "vtkCamera.h"
#include "vtkDataSet.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"

#include <algorithm>
#include <cmath>

namespace wfpv {

void fitClippingRange(vtkCamera* camera, vtkInformationVector** inputs, int ports)
{
  double eye[3], focal[3], d[3];
  camera->GetPosition(eye);
  camera->GetFocalPoint(focal);
  vtkMath::Subtract(focal, eye, d);
  if (!(vtkMath::Normalize(d) > 0))
    return;
  double nearest = HUGE_VAL, farthest = -HUGE_VAL;
  for (int port = 0; port < ports; ++port)
    for (int c = 0; c < inputs[port]->GetNumberOfInformationObjects(); ++c)
    {
      vtkDataSet* data = vtkDataSet::GetData(inputs[port], c);
      if (!data || data->GetNumberOfPoints() == 0)
        continue;
      double b[6];
      data->GetBounds(b);
      for (int k = 0; k < 8; ++k)
      {
        const double p[3] = { b[k & 1] - eye[0], b[2 + ((k >> 1) & 1)] - eye[1], b[4 + ((k >> 2) & 1)] - eye[2] };
        const double depth = vtkMath::Dot(p, d);
        if (std::isfinite(depth))
        {
          nearest = std::min(nearest, depth);
          farthest = std::max(farthest, depth);
        }
      }
    }
  if (!(farthest > 0))
    return;
  const double far = farthest * 1.01;
  // (near at least 1e-3 of far, as VTK's renderer keeps it: what the view clips, this clips)
  camera->SetClippingRange(std::max(nearest * 0.99, far * 1e-3), far);
}

}  // namespace wfpv
