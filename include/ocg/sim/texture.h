#pragma once
// Procedural textures with many distinct corners for ORB: multi-scale noise, blobs and
// print-like strokes and letters, different for every seed.

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace ocg::sim {

// A size x size BGR texture, deterministic in seed, for a surface span_metres wide.
// Features have physical sizes (centimetres) and a constant density per square metre,
// so a wall and a cup look equally detailed from the same distance; small surfaces get
// a minimum number of features.
cv::Mat MakeTexture(std::uint64_t seed, int size, double span_metres);

}  // namespace ocg::sim

namespace ocg::sim {

// Materials of the realistic look: natural texture statistics (plain paint with a few
// posters, carpet, wood grain, cloth, paper and printed labels) instead of the dense
// procedural patterns.
enum class Material {
  kPaint,        // walls: plain paint, a few posters, switches and sockets
  kCeiling,      // plain paint
  kCarpet,       // floor
  kWood,         // table legs and other bare wood
  kDesk,         // table top: wood under papers, notes, pens and cables
  kCabinet,      // wood doors with seams, handles and labels
  kBookShelf,    // shelf: wood with rows of book spines
  kFabricPanel,  // the partition: office divider cloth with pinned notes
  kBook,         // cover with title, picture and text
  kPrinted,      // cups, bottles, vases, bowls: plain surface with a printed label
  kKeyboard,     // key grid with letters
  kScreen,       // monitor: bezel and desktop with windows and text
  kLaptop,       // brushed metal with a logo
  kPlastic,      // mouse, phone, remote: dark plastic, a few buttons
  kCloth,        // teddy bear: fur
  kPlant,        // leaves
  kClockFace,    // white face, ticks and numbers
};
Material FurnitureMaterial(const std::string& furniture_name);
Material ObjectMaterial(int coco_class_id);

// A size x size BGR texture of the material for a surface span_metres wide, deterministic
// in seed; details (letters, keys, grain) have physical sizes.
cv::Mat MakeMaterialTexture(Material material, std::uint64_t seed, int size, double span_metres);

}  // namespace ocg::sim
