#include "ocg/detect/onnx_file.h"

#include <algorithm>
#include <set>
#include <string_view>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"

namespace ocg {
namespace {

// Protobuf wire format: a message is a run of (field number, wire type) keys, each
// followed by a varint (type 0), 8 bytes (1), a length-prefixed run (2) or 4 bytes (5).
class WireReader {
 public:
  WireReader(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  bool AtEnd() const { return pos_ >= bytes_.size(); }

  std::uint64_t Varint() {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= bytes_.size()) Fail("a number runs past the end");
      const auto byte = static_cast<unsigned char>(bytes_[pos_++]);
      value |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return value;
    }
    Fail("a number is longer than 10 bytes");
  }

  // Next field: its number, wire type, and for type 2 its bytes; other types are skipped.
  bool Next(int* field, int* type, std::string_view* payload) {
    if (AtEnd()) return false;
    const std::uint64_t key = Varint();
    *field = static_cast<int>(key >> 3);
    *type = static_cast<int>(key & 7);
    switch (*type) {
      case 0:
        last_varint_ = Varint();
        break;
      case 1:
        Skip(8);
        break;
      case 2: {
        const std::uint64_t length = Varint();
        if (length > bytes_.size() - pos_) Fail("a field runs past the end");
        *payload = bytes_.substr(pos_, length);
        pos_ += length;
        break;
      }
      case 5:
        Skip(4);
        break;
      default:
        Fail("unknown wire type " + std::to_string(*type));
    }
    return true;
  }
  std::uint64_t last_varint() const { return last_varint_; }

 private:
  void Skip(std::size_t n) {
    if (n > bytes_.size() - pos_) Fail("a field runs past the end");
    pos_ += n;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw ParseError(path_ + ": not an ONNX model (" + what + " at byte " + std::to_string(pos_) +
                     ")");
  }
  std::string_view bytes_;
  const std::string& path_;
  std::size_t pos_ = 0;
  std::uint64_t last_varint_ = 0;
};

// Field numbers of onnx.proto.
constexpr int kModelGraph = 7;
constexpr int kGraphInitializer = 5;
constexpr int kGraphInput = 11;
constexpr int kTensorName = 8;
constexpr int kValueInfoName = 1;
constexpr int kValueInfoType = 2;
constexpr int kTypeTensor = 1;
constexpr int kTensorTypeShape = 2;
constexpr int kShapeDim = 1;
constexpr int kDimValue = 1;

std::string_view SubMessage(std::string_view message, int wanted, const std::string& path) {
  WireReader reader(message, path);
  int field = 0;
  int type = 0;
  std::string_view payload;
  while (reader.Next(&field, &type, &payload)) {
    if (field == wanted && type == 2) return payload;
  }
  return {};
}

std::string StringField(std::string_view message, int wanted, const std::string& path) {
  return std::string(SubMessage(message, wanted, path));
}

std::vector<std::int64_t> Dims(std::string_view value_info, const std::string& path) {
  const std::string_view type = SubMessage(value_info, kValueInfoType, path);
  const std::string_view tensor = SubMessage(type, kTypeTensor, path);
  const std::string_view shape = SubMessage(tensor, kTensorTypeShape, path);
  std::vector<std::int64_t> dims;
  WireReader reader(shape, path);
  int field = 0;
  int kind = 0;
  std::string_view dim;
  while (reader.Next(&field, &kind, &dim)) {
    if (field != kShapeDim || kind != 2) continue;
    std::int64_t size = -1;
    WireReader dim_reader(dim, path);
    int dim_field = 0;
    int dim_kind = 0;
    std::string_view unused;
    while (dim_reader.Next(&dim_field, &dim_kind, &unused)) {
      if (dim_field == kDimValue && dim_kind == 0) {
        size = static_cast<std::int64_t>(dim_reader.last_varint());
      }
    }
    dims.push_back(size > 0 ? size : -1);
  }
  return dims;
}

}  // namespace

std::vector<OnnxInput> ReadOnnxInputs(const std::string& path) {
  const std::string bytes = ReadTextFile(path);
  const std::string_view graph = SubMessage(bytes, kModelGraph, path);
  if (graph.empty()) throw ParseError(path + ": not an ONNX model (no graph)");
  std::set<std::string> initializers;
  std::vector<std::string_view> inputs;
  WireReader reader(graph, path);
  int field = 0;
  int type = 0;
  std::string_view payload;
  while (reader.Next(&field, &type, &payload)) {
    if (type != 2) continue;
    if (field == kGraphInitializer) initializers.insert(StringField(payload, kTensorName, path));
    if (field == kGraphInput) inputs.push_back(payload);
  }
  std::vector<OnnxInput> result;
  for (std::string_view info : inputs) {
    OnnxInput input;
    input.name = StringField(info, kValueInfoName, path);
    if (initializers.count(input.name)) continue;
    input.dims = Dims(info, path);
    result.push_back(std::move(input));
  }
  return result;
}

}  // namespace ocg
