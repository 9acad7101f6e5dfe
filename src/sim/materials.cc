// Materials of the realistic look (texture.h). Real indoor frames have most of their
// corners on a few printed or cluttered things (labels, keyboards, book spines, posters)
// and large plain areas (walls, floor, furniture) whose texture stays under FAST's
// contrast threshold; the materials reproduce that split.

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "ocg/sim/texture.h"

namespace ocg::sim {
namespace {

// Smooth noise in [-1, 1] with `cells` lattice cells across (anisotropic with cells_y).
cv::Mat SmoothNoise(cv::RNG& rng, int size, int cells_x, int cells_y) {
  cv::Mat coarse(cells_y, cells_x, CV_32FC1);
  rng.fill(coarse, cv::RNG::UNIFORM, cv::Scalar(-1), cv::Scalar(1));
  cv::Mat fine;
  cv::resize(coarse, fine, cv::Size(size, size), 0, 0, cv::INTER_CUBIC);
  return fine;
}

// A base colour modulated by noise: shade multiplies every channel.
cv::Mat Tinted(const cv::Scalar& colour, const cv::Mat& shade) {
  std::vector<cv::Mat> channels(3);
  for (int c = 0; c < 3; ++c) channels[static_cast<std::size_t>(c)] = shade * colour[c];
  cv::Mat merged, image;
  cv::merge(channels, merged);
  merged.convertTo(image, CV_8UC3);
  return image;
}

cv::Scalar Jitter(cv::RNG& rng, const cv::Scalar& colour, double amount) {
  return cv::Scalar(std::clamp(colour[0] + rng.uniform(-amount, amount), 0.0, 255.0),
                    std::clamp(colour[1] + rng.uniform(-amount, amount), 0.0, 255.0),
                    std::clamp(colour[2] + rng.uniform(-amount, amount), 0.0, 255.0));
}

cv::Scalar Pick(cv::RNG& rng, std::initializer_list<cv::Scalar> palette) {
  return Jitter(rng, palette.begin()[rng.uniform(0, static_cast<int>(palette.size()))], 12);
}

// Lines of print-like words in rect: letter height in texels.
void Print(cv::Mat& image, cv::RNG& rng, const cv::Rect& rect, double letter_height,
           const cv::Scalar& ink, double fill = 0.8) {
  static const char kLetters[] = "abcdefghiklmnoprstuwyzABCDEFHKLMNPRST0123456789";
  if (letter_height < 1.5) {  // letters below a texel read as grey bars of words
    const int line = std::max(1, static_cast<int>(letter_height));
    for (int y = rect.y + line; y < rect.y + rect.height; y += 3 * line) {
      for (int x = rect.x; x < rect.x + rect.width * fill;) {
        const int word = rng.uniform(2, 8) * line;
        cv::rectangle(image, cv::Rect(x, y, std::min(word, rect.x + rect.width - x), line),
                      (ink + cv::Scalar::all(150)) * 0.5, cv::FILLED);
        x += word + 2 * line;
      }
    }
    return;
  }
  const double scale = letter_height / 22.0;
  const int thickness = std::max(1, static_cast<int>(letter_height / 12));
  for (double y = rect.y + letter_height * 1.2; y < rect.y + rect.height;
       y += letter_height * 1.7) {
    double x = rect.x;
    while (x < rect.x + rect.width * fill) {
      std::string word;
      for (int k = rng.uniform(2, 8); k > 0; --k)
        word += kLetters[rng.uniform(0, sizeof(kLetters) - 1)];
      int baseline = 0;
      const cv::Size extent =
          cv::getTextSize(word, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
      if (x + extent.width > rect.x + rect.width) break;
      cv::putText(image, word, cv::Point(static_cast<int>(x), static_cast<int>(y)),
                  cv::FONT_HERSHEY_SIMPLEX, scale, ink, thickness, cv::LINE_AA);
      x += extent.width + letter_height * 0.6;
    }
  }
}

// A picture: soft coloured blobs on a background (photos and drawings on covers, posters).
void Picture(cv::Mat& image, cv::RNG& rng, cv::Rect rect) {
  rect &= cv::Rect(0, 0, image.cols, image.rows);
  if (rect.empty()) return;
  cv::rectangle(image, rect, Pick(rng, {{200, 190, 170}, {90, 120, 150}, {60, 140, 90}}),
                cv::FILLED);
  const int blobs = rng.uniform(3, 8);
  for (int i = 0; i < blobs; ++i) {
    const cv::Point centre(rect.x + rng.uniform(0, std::max(1, rect.width)),
                           rect.y + rng.uniform(0, std::max(1, rect.height)));
    const cv::Size axes(std::max(1, rng.uniform(rect.width / 10 + 1, rect.width / 3 + 2)),
                        std::max(1, rng.uniform(rect.height / 10 + 1, rect.height / 3 + 2)));
    cv::Mat roi = image(rect);
    cv::ellipse(roi, centre - rect.tl(), axes, rng.uniform(0, 180), 0, 360,
                Jitter(rng, cv::Scalar(110, 110, 110), 100), cv::FILLED, cv::LINE_AA);
  }
}

cv::Mat Paint(cv::RNG& rng, int size, const cv::Scalar& colour) {
  cv::Mat shade = SmoothNoise(rng, size, 5, 5) * 0.015 + 1.0;
  return Tinted(colour, shade);
}

cv::Mat Wood(cv::RNG& rng, int size, double texels_per_metre) {
  const cv::Scalar colour =
      Pick(rng, {{60, 105, 150}, {45, 80, 120}, {90, 140, 185}, {35, 55, 80}});
  cv::Mat warp = SmoothNoise(rng, size, 4, 12) * (0.02 * texels_per_metre);
  cv::Mat fibre = SmoothNoise(rng, size, 6, std::max(8, size / 3));
  const double period = 0.012 * texels_per_metre;  // growth rings about a centimetre apart
  cv::Mat shade(size, size, CV_32FC1);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double ring = std::sin(2 * M_PI * (y + warp.at<float>(y, x)) / std::max(2.0, period));
      shade.at<float>(y, x) = static_cast<float>(1.0 + 0.035 * ring + 0.03 * fibre.at<float>(y, x));
    }
  }
  return Tinted(colour, shade);
}

cv::Mat Fibres(cv::RNG& rng, int size, const cv::Scalar& colour, double amplitude) {
  cv::Mat shade = SmoothNoise(rng, size, 6, 6) * 0.03 + 1.0;
  cv::Mat grain(size, size, CV_32FC1);
  rng.fill(grain, cv::RNG::NORMAL, cv::Scalar(0), cv::Scalar(amplitude));
  cv::GaussianBlur(grain, grain, cv::Size(), 0.8);
  shade += grain;
  return Tinted(colour, shade);
}

}  // namespace

Material FurnitureMaterial(const std::string& name) {
  if (name.rfind("wall", 0) == 0) return Material::kPaint;
  if (name == "ceiling") return Material::kCeiling;
  if (name == "floor") return Material::kCarpet;
  if (name.rfind("shelf", 0) == 0) return Material::kBookShelf;
  if (name == "table_top") return Material::kDesk;
  if (name.rfind("cabinet", 0) == 0) return Material::kCabinet;
  if (name == "partition") return Material::kFabricPanel;
  return Material::kWood;
}

Material ObjectMaterial(int coco_class_id) {
  switch (coco_class_id) {
    case 73:
      return Material::kBook;
    case 66:
      return Material::kKeyboard;
    case 62:
      return Material::kScreen;
    case 63:
      return Material::kLaptop;
    case 64:
    case 65:
    case 67:
      return Material::kPlastic;
    case 77:
      return Material::kCloth;
    case 58:
      return Material::kPlant;
    case 74:
      return Material::kClockFace;
    default:
      return Material::kPrinted;
  }
}

cv::Mat MakeMaterialTexture(Material material, std::uint64_t seed, int size, double span_metres) {
  cv::RNG rng(seed * 0xd1342543de82ef95ULL + 3);
  const double tpm = size / span_metres;  // texels per metre
  auto texels = [&](double metres) { return std::max(1, static_cast<int>(metres * tpm)); };
  const double area = span_metres * span_metres;
  const cv::Scalar ink(35, 30, 30);
  cv::Mat image;
  switch (material) {
    case Material::kPaint: {
      image = Paint(rng, size, Pick(rng, {{225, 230, 232}, {200, 215, 222}, {205, 210, 200}}));
      // Posters, notices and framed pictures at about one per square metre, switches and
      // sockets.
      for (int i = static_cast<int>(rng.uniform(0.9, 1.2) * area); i > 0; --i) {
        const cv::Rect poster(rng.uniform(0, size), rng.uniform(0, size),
                              texels(rng.uniform(0.3, 0.6)), texels(rng.uniform(0.4, 0.8)));
        cv::rectangle(image, poster, cv::Scalar(235, 238, 240), cv::FILLED);
        const cv::Rect picture(poster.x + poster.width / 10, poster.y + poster.height / 10,
                               poster.width * 8 / 10, poster.height * 4 / 10);
        Picture(image, rng, picture);
        Print(
            image, rng,
            cv::Rect(picture.x, picture.y + picture.height, picture.width, poster.height * 4 / 10),
            texels(0.012), ink);
      }
      for (int i = static_cast<int>(rng.uniform(0.1, 0.2) * area); i > 0; --i) {
        const cv::Rect plate(rng.uniform(0, size), rng.uniform(0, size), texels(0.08),
                             texels(0.08));
        cv::rectangle(image, plate, cv::Scalar(245, 245, 245), cv::FILLED, cv::LINE_AA);
        cv::rectangle(image, plate, cv::Scalar(170, 170, 170), 1, cv::LINE_AA);
      }
      return image;
    }
    case Material::kCeiling:
      return Paint(rng, size, cv::Scalar(238, 240, 240));
    case Material::kCarpet: {
      image = Fibres(rng, size, Pick(rng, {{110, 105, 100}, {120, 95, 80}, {90, 95, 100}}), 0.05);
      // Flecks of darker and lighter yarn, a centimetre or two across.
      for (int i = static_cast<int>(150 * area); i > 0; --i) {
        cv::circle(image, cv::Point(rng.uniform(0, size), rng.uniform(0, size)),
                   texels(rng.uniform(0.005, 0.012)), Jitter(rng, cv::Scalar(100, 100, 100), 90),
                   cv::FILLED);
      }
      return image;
    }
    case Material::kWood:
      return Wood(rng, size, tpm);
    case Material::kDesk: {
      image = Wood(rng, size, tpm);
      // About twenty things per square metre: sheets with print, sticky notes, pens, cables.
      for (int i = static_cast<int>(rng.uniform(16.0, 24.0) * area); i > 0; --i) {
        const cv::Point at(rng.uniform(0, size), rng.uniform(0, size));
        switch (rng.uniform(0, 4)) {
          case 0: {
            const cv::Rect sheet(at, cv::Size(texels(0.21), texels(0.297)));
            cv::rectangle(image, sheet, cv::Scalar(238, 240, 242), cv::FILLED);
            Print(image, rng,
                  cv::Rect(sheet.x + sheet.width / 8, sheet.y + sheet.height / 10,
                           sheet.width * 3 / 4, sheet.height * 3 / 4),
                  texels(0.004), ink);
            break;
          }
          case 1:
            cv::rectangle(image, cv::Rect(at, cv::Size(texels(0.075), texels(0.075))),
                          Pick(rng, {{120, 240, 250}, {180, 140, 250}, {150, 240, 150}}),
                          cv::FILLED);
            break;
          case 2: {
            const double angle = rng.uniform(0.0, M_PI);
            const cv::Point end = at + cv::Point(static_cast<int>(texels(0.14) * std::cos(angle)),
                                                 static_cast<int>(texels(0.14) * std::sin(angle)));
            cv::line(image, at, end, Pick(rng, {{30, 30, 30}, {180, 60, 30}, {30, 30, 180}}),
                     texels(0.009), cv::LINE_AA);
            break;
          }
          default: {
            std::vector<cv::Point> cable = {at};
            double heading = rng.uniform(0.0, 2 * M_PI);
            for (int k = 0; k < 12; ++k) {
              heading += rng.uniform(-0.6, 0.6);
              cable.push_back(cable.back() +
                              cv::Point(static_cast<int>(texels(0.05) * std::cos(heading)),
                                        static_cast<int>(texels(0.05) * std::sin(heading))));
            }
            cv::polylines(image, cable, false, cv::Scalar(25, 25, 25), texels(0.006), cv::LINE_AA);
          }
        }
      }
      return image;
    }
    case Material::kCabinet: {
      image = Wood(rng, size, tpm);
      // Doors 45 cm wide with a seam, a handle and now and then a label.
      const cv::Scalar seam = cv::Scalar(30, 40, 50);
      for (int x = texels(0.45); x < size; x += texels(0.45)) {
        cv::line(image, cv::Point(x, 0), cv::Point(x, size), seam, std::max(1, texels(0.004)));
        const int handle_y = texels(rng.uniform(0.3, 0.6));
        cv::rectangle(image, cv::Rect(x - texels(0.04), handle_y, texels(0.015), texels(0.12)),
                      cv::Scalar(190, 190, 195), cv::FILLED, cv::LINE_AA);
        if (rng.uniform(0.0, 1.0) < 0.6) {
          const cv::Rect label(x - texels(0.3), texels(rng.uniform(0.1, 0.3)), texels(0.1),
                               texels(0.05));
          cv::rectangle(image, label, cv::Scalar(240, 240, 240), cv::FILLED);
          Print(image, rng, label, texels(0.012), ink);
        }
      }
      for (int y = texels(0.5); y < size; y += texels(0.5)) {
        cv::line(image, cv::Point(0, y), cv::Point(size, y), seam, std::max(1, texels(0.004)));
      }
      return image;
    }
    case Material::kBookShelf: {
      image = Wood(rng, size, tpm);
      // Shelf boards every 35 cm, books standing on them.
      for (double board = 0.05; board < span_metres; board += 0.35) {
        const int floor_y = texels(board + 0.3);
        int x = texels(0.03);
        while (x < size - texels(0.05)) {
          const int width = texels(rng.uniform(0.02, 0.05));
          const int height = texels(rng.uniform(0.18, 0.28));
          if (rng.uniform(0.0, 1.0) < 0.25) {  // gaps between groups of books
            x += texels(rng.uniform(0.05, 0.2));
            continue;
          }
          const cv::Rect spine(x, floor_y - height, width, height);
          cv::rectangle(
              image, spine,
              Pick(rng,
                   {{40, 40, 140}, {130, 60, 30}, {40, 110, 40}, {200, 200, 195}, {30, 30, 30}}),
              cv::FILLED);
          if (rng.uniform(0.0, 1.0) < 0.5) {
            cv::rectangle(image, cv::Rect(x, spine.y + height / 6, width, texels(0.015)),
                          cv::Scalar(60, 190, 220), cv::FILLED);
          }
          x += width + 1;
        }
      }
      return image;
    }
    case Material::kFabricPanel: {
      image = Fibres(rng, size, Pick(rng, {{120, 110, 95}, {95, 100, 105}, {80, 110, 130}}), 0.04);
      for (int i = static_cast<int>(rng.uniform(5.0, 7.0) * area); i > 0; --i) {  // pinned notes
        const cv::Rect note(rng.uniform(0, size), rng.uniform(0, size), texels(0.21), texels(0.28));
        cv::rectangle(image, note, cv::Scalar(236, 240, 242), cv::FILLED);
        Print(image, rng,
              cv::Rect(note.x + note.width / 8, note.y, note.width * 3 / 4, note.height * 3 / 4),
              texels(0.01), ink);
      }
      return image;
    }
    case Material::kBook: {
      image = Paint(
          rng, size,
          Pick(rng, {{40, 40, 150}, {140, 80, 30}, {220, 220, 215}, {50, 130, 60}, {30, 30, 35}}));
      const cv::Rect picture(size / 8, size * 3 / 8, size * 3 / 4, size * 3 / 8);
      Picture(image, rng, picture);
      Print(image, rng, cv::Rect(size / 8, size / 16, size * 3 / 4, size / 4), texels(0.018),
            cv::Scalar(235, 235, 235), 0.7);
      return image;
    }
    case Material::kPrinted: {
      image = Paint(
          rng, size,
          Pick(rng,
               {{235, 235, 235}, {40, 40, 160}, {160, 100, 40}, {60, 60, 60}, {90, 170, 200}}));
      // A label band round the middle with a logo and small print.
      const cv::Rect band(0, size * 3 / 10, size, size * 3 / 10);
      cv::rectangle(image, band, Pick(rng, {{240, 240, 240}, {40, 200, 230}, {200, 90, 40}}),
                    cv::FILLED);
      cv::circle(image, cv::Point(size / 4, band.y + band.height / 2), band.height / 3,
                 Pick(rng, {{30, 30, 200}, {200, 60, 30}, {30, 140, 30}}), cv::FILLED, cv::LINE_AA);
      Print(image, rng, cv::Rect(size / 2, band.y, size / 2, band.height), texels(0.008), ink);
      return image;
    }
    case Material::kKeyboard: {
      image = Paint(rng, size, cv::Scalar(45, 45, 48));
      const int key = texels(0.019);
      const int pitch = std::max(key + 1, texels(0.0195));
      static const char kKeys[] = "QWERTYUIOPASDFGHJKLZXCVBNM1234567890";
      for (int y = pitch / 4; y + key < size; y += pitch) {
        for (int x = pitch / 4; x + key < size; x += pitch) {
          cv::rectangle(image, cv::Rect(x, y, key - 1, key - 1), cv::Scalar(70, 70, 74),
                        cv::FILLED);
          const std::string letter(1, kKeys[rng.uniform(0, sizeof(kKeys) - 1)]);
          cv::putText(image, letter, cv::Point(x + key / 4, y + key * 2 / 3),
                      cv::FONT_HERSHEY_PLAIN, std::max(0.3, key / 30.0), cv::Scalar(200, 200, 200),
                      1, cv::LINE_AA);
        }
      }
      return image;
    }
    case Material::kScreen: {
      image = Paint(rng, size, cv::Scalar(25, 25, 28));
      const cv::Rect screen(size / 20, size / 20, size * 9 / 10, size * 9 / 10);
      cv::rectangle(image, screen, Pick(rng, {{120, 80, 40}, {60, 60, 60}, {140, 120, 90}}),
                    cv::FILLED);
      for (int i = rng.uniform(1, 3); i > 0; --i) {  // windows with text
        const cv::Rect window(screen.x + rng.uniform(0, screen.width / 2),
                              screen.y + rng.uniform(0, screen.height / 3), screen.width / 2,
                              screen.height / 2);
        cv::rectangle(image, window & screen, cv::Scalar(245, 245, 245), cv::FILLED);
        cv::rectangle(
            image,
            cv::Rect(window.x, window.y, window.width, std::max(2, window.height / 10)) & screen,
            cv::Scalar(160, 110, 60), cv::FILLED);
        Print(image, rng, window & screen, texels(0.008), ink);
      }
      return image;
    }
    case Material::kLaptop: {
      image = Fibres(rng, size, Pick(rng, {{190, 190, 195}, {70, 70, 75}}), 0.015);
      cv::circle(image, cv::Point(size / 2, size / 2), texels(0.025), cv::Scalar(230, 230, 230),
                 cv::FILLED, cv::LINE_AA);
      return image;
    }
    case Material::kPlastic: {
      image = Paint(rng, size, Pick(rng, {{30, 30, 32}, {200, 200, 205}, {60, 60, 65}}));
      for (int i = rng.uniform(2, 7); i > 0; --i) {
        cv::circle(image, cv::Point(rng.uniform(0, size), rng.uniform(0, size)), texels(0.006),
                   Pick(rng, {{150, 150, 150}, {40, 40, 200}, {40, 160, 40}}), cv::FILLED,
                   cv::LINE_AA);
      }
      return image;
    }
    case Material::kCloth:
      image = Fibres(rng, size, Pick(rng, {{50, 90, 140}, {70, 110, 160}, {200, 200, 205}}), 0.12);
      for (int eye = 0; eye < 2; ++eye) {
        cv::circle(image, cv::Point(size * (2 + eye) / 5, size / 4), texels(0.012),
                   cv::Scalar(20, 20, 20), cv::FILLED, cv::LINE_AA);
      }
      return image;
    case Material::kPlant: {
      image = Paint(rng, size, cv::Scalar(40, 70, 40));
      for (int i = 0; i < 40; ++i) {
        cv::ellipse(image, cv::Point(rng.uniform(0, size), rng.uniform(0, size)),
                    cv::Size(texels(0.04), texels(0.012)), rng.uniform(0, 180), 0, 360,
                    Jitter(rng, cv::Scalar(50, 140, 60), 30), cv::FILLED, cv::LINE_AA);
      }
      return image;
    }
    case Material::kClockFace: {
      image = Paint(rng, size, cv::Scalar(240, 240, 240));
      const cv::Point centre(size / 2, size / 2);
      for (int hour = 0; hour < 12; ++hour) {
        const double angle = hour * M_PI / 6;
        const cv::Point2d direction(std::sin(angle), -std::cos(angle));
        cv::line(image, centre + cv::Point(direction * (size * 0.42)),
                 centre + cv::Point(direction * (size * 0.36)), ink, 2, cv::LINE_AA);
      }
      cv::line(image, centre, centre + cv::Point(size / 5, -size / 8), ink, 3, cv::LINE_AA);
      cv::line(image, centre, centre + cv::Point(-size / 12, -size / 3), ink, 2, cv::LINE_AA);
      return image;
    }
  }
  return image;
}

}  // namespace ocg::sim
