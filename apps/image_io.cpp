#include "image_io.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace wfapp {

float linearToSrgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writePng(const wf::ImageRGBA& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0) throw std::runtime_error(path + ": empty image");
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(data->GetScalarPointer());
  for (int y = 0; y < image.height; ++y) {
    // VTK images start at the bottom row.
    const int row = image.height - 1 - y;
    for (int x = 0; x < image.width; ++x) {
      const glm::vec4& p = image.at(x, y);
      unsigned char* o = out + 3 * (size_t(row) * image.width + x);
      for (int c = 0; c < 3; ++c) o[c] = (unsigned char)std::lround(255.0f * linearToSrgb(p[c]));
    }
  }
  const std::filesystem::path target(path);
  std::string tmpName = target.filename().string();  // hidden sibling: ".NAME.tmp"
  tmpName.insert(0, 1, '.');
  tmpName += ".tmp";
  const std::filesystem::path tmp = target.parent_path() / tmpName;
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(tmp.string().c_str());
  writer->SetInputData(data);
  writer->Write();
  std::error_code ec;
  if (writer->GetErrorCode() != 0 || !std::filesystem::exists(tmp)) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write PNG");
  }
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    const std::string why = ec.message();  // before remove() overwrites ec
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write PNG (" + why + ")");
  }
}

}  // namespace wfapp
