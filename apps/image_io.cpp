#include "image_io.h"

#include "cli.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <fstream>

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

float srgbToLinear(float e) {
  if (!(e > 0.0f)) return 0.0f;
  if (e >= 1.0f) return 1.0f;
  return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
}

wf::ImageRGBA readPng(const std::string& path, size_t maxPixels) {
  // libpng (through VTK) trusts nothing it has not checked, but VTK's reader reports a bad file
  // only by its error code and a message on its own output: check the signature first so that
  // "not a PNG" is one clear line, and let VTK decode.
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": cannot open the image");
  unsigned char sig[8] = {0};
  in.read(reinterpret_cast<char*>(sig), 8);
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  if (in.gcount() != 8 || !std::equal(sig, sig + 8, png)) throw UsageError(path + ": not a PNG image");
  in.close();
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  int ext[6];
  reader->GetDataExtent(ext);
  const long long w = ext[1] - ext[0] + 1, h = ext[3] - ext[2] + 1;
  if (w <= 0 || h <= 0) throw UsageError(path + ": the PNG has no pixels");
  if (size_t(w) * size_t(h) > maxPixels)
    throw UsageError(path + ": the PNG is " + std::to_string(w) + "x" + std::to_string(h) + ", more than the " +
                     std::to_string(maxPixels) + " pixels a texture may have");
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  vtkDataArray* a = data ? data->GetPointData()->GetScalars() : nullptr;
  if (reader->GetErrorCode() != 0 || !a || a->GetNumberOfTuples() != w * h)
    throw UsageError(path + ": the PNG could not be decoded (truncated or corrupt)");
  const int nc = a->GetNumberOfComponents();
  const double scale = a->GetDataType() == VTK_UNSIGNED_SHORT ? 1.0 / 65535.0 : 1.0 / 255.0;
  wf::ImageRGBA img{int(w), int(h)};
  for (long long y = 0; y < h; ++y)
    for (long long x = 0; x < w; ++x) {
      const vtkIdType t = vtkIdType((h - 1 - y) * w + x);  // VTK rows start at the bottom
      auto comp = [&](int c) { return float(a->GetComponent(t, c) * scale); };
      glm::vec4 p(1.0f);
      if (nc <= 2) {
        p = glm::vec4(glm::vec3(srgbToLinear(comp(0))), nc == 2 ? comp(1) : 1.0f);
      } else {
        for (int c = 0; c < 3; ++c) p[c] = srgbToLinear(comp(c));
        p.w = nc >= 4 ? comp(3) : 1.0f;
      }
      img.at(int(x), int(y)) = p;
    }
  return img;
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
