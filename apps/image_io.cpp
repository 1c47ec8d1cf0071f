#include "image_io.h"

#include "cli.h"

#include "core/srgb.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkUnsignedCharArray.h>

#include <png.h>

#include <cstring>
#include <fstream>
#include <vector>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace wfapp {

float linearToSrgb(float v) { return wf::linearToSrgb(v); }

wf::ImageRGBA readPng(const std::string& path, size_t maxPixels) {
  // libpng's simplified API: it checks every chunk, reports a bad file as a message instead of
  // longjmp-ing through our stack (VTK's PNG reader crashes on a corrupt file), and converts to
  // 16-bit linear light itself (sRGB or the file's gAMA decoded). Alpha is composited over black.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw UsageError(path + ": is a directory, not a PNG image");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": cannot open the image");
  unsigned char sig[8] = {0};
  in.read(reinterpret_cast<char*>(sig), 8);
  if (in.gcount() != 8 || png_sig_cmp(sig, 0, 8) != 0) throw UsageError(path + ": not a PNG image");
  in.close();
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw UsageError(path + ": bad PNG (" + std::string(image.message) + ")");
  const size_t w = image.width, h = image.height;
  if (w == 0 || h == 0 || w * h > maxPixels) {
    png_image_free(&image);
    throw UsageError(path + ": the PNG is " + std::to_string(w) + "x" + std::to_string(h) + ", more than the " +
                     std::to_string(maxPixels) + " pixels a texture may have");
  }
  image.format = PNG_FORMAT_LINEAR_RGB;
  std::vector<png_uint_16> buffer(PNG_IMAGE_SIZE(image) / sizeof(png_uint_16));
  if (!png_image_finish_read(&image, nullptr, buffer.data(), 0, nullptr))
    throw UsageError(path + ": bad PNG (" + std::string(image.message) + ")");  // finish_read frees on failure
  wf::ImageRGBA img{int(w), int(h)};
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x) {
      const png_uint_16* p = &buffer[3 * (y * w + x)];
      img.at(int(x), int(y)) = glm::vec4(p[0] / 65535.0f, p[1] / 65535.0f, p[2] / 65535.0f, 1.0f);
    }
  return img;
}

void writePng(const wf::ImageRGBA& image, const std::string& path, int compression) {
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
  writer->SetCompressionLevel(std::clamp(compression, 0, 9));
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
