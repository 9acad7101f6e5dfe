#pragma once
// What an ONNX file says about its image input, read from the file itself (a few fields of
// its protobuf encoding), so a model's input size needs no option.

#include <cstdint>
#include <string>
#include <vector>

namespace ocg {

struct OnnxInput {
  std::string name;
  // Dimensions as stored; -1 for a dimension without a fixed size (dim_param or none).
  std::vector<std::int64_t> dims;
};

// The graph's inputs that are not initializers (weights), in file order. Throws FileError
// when the file cannot be read, ParseError naming the file when it is not an ONNX model.
std::vector<OnnxInput> ReadOnnxInputs(const std::string& path);

}  // namespace ocg
