// A C++17 VTK application using WireFur (docs/install.md): a CAD part read by the WireFur CAD
// reader, its edges drawn as shaded wire and a plane beside it grown with fur, both composited by
// the A-buffer render pass over the surfaces VTK draws, written to a PNG. Prints the pass's time
// and error estimate.
//   cad_and_fur PART.step OUT.png
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPlaneSource.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSMPTools.h>  // (compiles as C++17, not as C++20: what WireFur's headers must allow)
#include <vtkWindowToImageFilter.h>

#include <vtkWireFurCADReader.h>
#include <vtkWireFurFurGenerator.h>
#include <vtkWireFurRenderPass.h>

#include <cstdio>

int main(int argc, char** argv)
{
  if (argc != 3)
  {
    std::fprintf(stderr, "usage: cad_and_fur PART.step OUT.png\n");
    return 2;
  }
  vtkNew<vtkWireFurCADReader> part;
  part->SetFileName(argv[1]);
  part->ReadInWorkerOn();  // a corrupt file cannot take this program down
  part->Update();
  if (!part->GetErrorMessage().empty())
    return 2;  // (the reader has said why, on one line)
  double b[6];
  part->GetOutput(0)->GetBounds(b);
  const double size = b[1] - b[0];

  vtkNew<vtkActor> faces, edges, skin, hair;
  vtkNew<vtkPolyDataMapper> facesMapper, edgesMapper, skinMapper, hairMapper;
  facesMapper->SetInputConnection(part->GetOutputPort(0));
  facesMapper->ScalarVisibilityOff();
  faces->SetMapper(facesMapper);
  faces->GetProperty()->SetColor(0.85, 0.55, 0.2);
  edgesMapper->SetInputConnection(part->GetOutputPort(1));
  edgesMapper->ScalarVisibilityOff();
  edges->SetMapper(edgesMapper);
  edges->GetProperty()->SetColor(0.8, 0.8, 0.85);
  edges->GetProperty()->SetSpecular(1.0);
  vtkWireFurRenderPass::Mark(edges, true);
  edges->GetPropertyKeys()->Set(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS(), 0.004 * size);

  // Fur on a plane beside the part (the texture coordinates vtkPlaneSource makes place the roots).
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(b[1] + 0.1 * size, b[2], b[4]);
  plane->SetPoint1(b[1] + 0.6 * size, b[2], b[4]);
  plane->SetPoint2(b[1] + 0.1 * size, b[3], b[4]);
  skinMapper->SetInputConnection(plane->GetOutputPort());
  skin->SetMapper(skinMapper);
  skin->GetProperty()->SetColor(0.35, 0.25, 0.15);
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetInputConnection(plane->GetOutputPort());
  fur->SetGridU(80);
  fur->SetGridV(80);
  fur->SetLength(0.08 * size);
  fur->SetThickness(0.002 * size);
  hairMapper->SetInputConnection(fur->GetOutputPort());
  hairMapper->ScalarVisibilityOff();
  hair->SetMapper(hairMapper);
  hair->GetProperty()->SetColor(0.9, 0.75, 0.55);
  vtkWireFurRenderPass::Mark(hair, true);
  hair->GetPropertyKeys()->Set(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS(), 0.002 * size);

  vtkNew<vtkRenderer> renderer;
  for (vtkActor* a : { faces.Get(), edges.Get(), skin.Get(), hair.Get() })
    renderer->AddActor(a);
  vtkNew<vtkWireFurRenderPass> pass;
  vtkNew<vtkRenderStepsPass> steps;
  pass->SetDelegatePass(steps);
  renderer->SetPass(pass);
  renderer->SetBackground(0.1, 0.1, 0.12);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Elevation(35);
  renderer->GetActiveCamera()->Azimuth(30);
  renderer->ResetCameraClippingRange();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(640, 480);
  window->AddRenderer(renderer);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> png;
  png->SetInputConnection(grab->GetOutputPort());
  png->SetFileName(argv[2]);
  png->Write();
  std::printf("A-buffer: %d marked props, %lld hairs, %.3f s, error estimate %.2e\n", pass->GetLastMarkedProps(),
    static_cast<long long>(fur->GetOutput()->GetNumberOfLines()), pass->GetLastRenderSeconds(),
    pass->GetLastErrorEstimate());
  return 0;
}
