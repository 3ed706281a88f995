#include "tools/eval/dataset.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace ellipsekit::eval {
namespace fs = std::filesystem;

namespace {

Status Invalid(const std::string& message) { return Status(StatusCode::kInvalidArgument, message); }

}  // namespace

bool IsImageExtension(const std::string& extension) {
  std::string ext = extension;
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
}

Status ParseDontCareBoxes(const std::string& text, const std::string& name,
                          std::map<std::string, std::vector<BoundingBox>>* out) {
  out->clear();
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string stem;
    if (!(fields >> stem)) continue;  // blank or comment
    BoundingBox box;
    std::string extra;
    if (!(fields >> box.x0 >> box.y0 >> box.x1 >> box.y1) || (fields >> extra) ||
        !std::isfinite(box.x0) || !std::isfinite(box.y0) || !std::isfinite(box.x1) ||
        !std::isfinite(box.y1)) {
      return Invalid(name + ":" + std::to_string(line_number) +
                     ": expected '<image stem> x0 y0 x1 y1'");
    }
    if (box.x1 < box.x0) std::swap(box.x0, box.x1);
    if (box.y1 < box.y0) std::swap(box.y0, box.y1);
    (*out)[stem].push_back(box);
  }
  return Status::Ok();
}

Status LoadDataset(const std::string& dir, Dataset* out) {
  *out = Dataset();
  out->root = dir;
  std::error_code ec;
  const fs::path root(dir);
  if (!fs::is_directory(root, ec)) return Invalid(dir + ": not a directory");
  const fs::path images_dir = root / "images";
  if (!fs::is_directory(images_dir, ec)) {
    return Invalid(images_dir.string() + ": missing (a dataset holds images/ and gt/)");
  }
  const fs::path gt_dir = root / "gt";

  std::vector<fs::path> files;
  for (fs::directory_iterator it(images_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    if (IsImageExtension(it->path().extension().string())) files.push_back(it->path());
  }
  if (ec) return Invalid(images_dir.string() + ": cannot list: " + ec.message());
  if (files.empty()) return Invalid(images_dir.string() + ": no images (png, jpg, bmp)");
  std::sort(files.begin(), files.end(),
            [](const fs::path& l, const fs::path& r) { return l.filename() < r.filename(); });

  std::set<std::string> stems;
  for (const fs::path& file : files) {
    DatasetImage item;
    item.stem = file.stem().string();
    item.image_path = file.string();
    item.truth_path = (gt_dir / (item.stem + ".txt")).string();
    if (!stems.insert(item.stem).second) {
      return Invalid(item.image_path + ": another image has the same stem '" + item.stem + "'");
    }
    if (!fs::is_regular_file(item.truth_path, ec)) {
      return Invalid(item.image_path + ": no ground truth file " + item.truth_path);
    }
    out->images.push_back(std::move(item));
  }

  const fs::path boxes = root / "border_boxes.txt";
  if (fs::exists(boxes, ec)) {
    std::ifstream in(boxes, std::ios::binary);
    if (!in) return Invalid(boxes.string() + ": cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    Status st = ParseDontCareBoxes(text.str(), boxes.string(), &out->dont_care);
    if (!st.ok()) return st;
    for (const auto& [stem, list] : out->dont_care) {
      if (!stems.count(stem)) {
        return Invalid(boxes.string() + ": names image '" + stem + "', which is not in images/");
      }
    }
  }
  return Status::Ok();
}

}  // namespace ellipsekit::eval
