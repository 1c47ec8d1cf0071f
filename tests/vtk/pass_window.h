// The window the render pass tests share: offscreen, W x H, camera at (0, 0, 5) looking at the
// origin (view angle 30, clipping range 1 ... 20), one white scene light from (1, 1, 2), black
// background, the pass set on the renderer.
#pragma once

#include "vtkWireFurRenderPass.h"

#include <vtkCamera.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

inline void setUpPassWindow(vtkRenderWindow* window, vtkRenderer* renderer, vtkWireFurRenderPass* pass, int width,
                            int height, int multiSamples = 0)
{
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(multiSamples);
  window->SetSize(width, height);
  window->AddRenderer(renderer);
  renderer->SetBackground(0, 0, 0);
  renderer->AutomaticLightCreationOff();
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(1, 1, 2);
  light->SetFocalPoint(0, 0, 0);
  light->SetPositional(false);
  light->SetIntensity(1.0);
  light->SetColor(1, 1, 1);
  renderer->AddLight(light);
  vtkCamera* c = renderer->GetActiveCamera();
  c->SetPosition(0, 0, 5);
  c->SetFocalPoint(0, 0, 0);
  c->SetViewUp(0, 1, 0);
  c->SetViewAngle(30);
  c->SetClippingRange(1, 20);
  renderer->SetPass(pass);
}
