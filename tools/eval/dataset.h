// A dataset directory (../shared/datasets/<set>, or one written by `ellipsekit scenes`):
//
//   DIR/images/<stem>.png|.jpg|.jpeg|.bmp   the images (extension case-insensitive)
//   DIR/gt/<stem>.txt                       ground truth, one `cx cy a b theta` per line (ellipse_io.h)
//   DIR/border_boxes.txt                    optional don't-care regions, see below
//
// Images are listed sorted by file name (byte order). Missing DIR/images, an empty images/
// folder, two images with the same stem, or an image without its gt/<stem>.txt is an error
// naming the path.
//
// border_boxes.txt (su2019_coin) lists ground truth that is unreliable because its box was cut
// by the image border. Its format is ours (the shipped file is empty): one box per line,
//   <image stem> x0 y0 x1 y1
// in the GT's pixel frame; blank lines and '#' comments are skipped. Scoring (metrics.h) drops
// ground truth whose centre lies in a box of its image and ignores detections whose centre lies
// in one unless they matched kept ground truth.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ellipsekit/types.h"
#include "tools/eval/overlap.h"

namespace ellipsekit::eval {

struct DatasetImage {
  std::string stem;        // file name without extension
  std::string image_path;  // DIR/images/<file>
  std::string truth_path;  // DIR/gt/<stem>.txt
};

struct Dataset {
  std::string root;
  std::vector<DatasetImage> images;                        // sorted by file name
  std::map<std::string, std::vector<BoundingBox>> dont_care;  // by image stem
};

// Lists the dataset at `dir` (and parses border_boxes.txt when present).
Status LoadDataset(const std::string& dir, Dataset* out);

// Parses border_boxes.txt text; `name` is used in "name:line: problem" messages.
Status ParseDontCareBoxes(const std::string& text, const std::string& name,
                          std::map<std::string, std::vector<BoundingBox>>* out);

// True for the image extensions listed above (case-insensitive, with the dot).
bool IsImageExtension(const std::string& extension);

}  // namespace ellipsekit::eval
