#include "euroc_folder.h"

#include "fuzz_input.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"

namespace ocg::fuzz {
namespace {

const std::string kEurocFolder = "euroc";

std::string ValidEurocFolder() {
  WriteInput(kEurocFolder + "/mav0/cam0/data.csv",
             "#timestamp [ns],filename\n"
             "1403715273262142976,1403715273262142976.png\n"
             "1403715273312143104,1403715273312143104.png\n");
  WriteInput(kEurocFolder + "/mav0/cam0/sensor.yaml",
             "%YAML:1.0\n"
             "sensor_type: camera\n"
             "T_BS:\n"
             "  cols: 4\n"
             "  rows: 4\n"
             "  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,\n"
             "         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,\n"
             "        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,\n"
             "         0.0, 0.0, 0.0, 1.0]\n"
             "rate_hz: 20\n"
             "resolution: [752, 480]\n"
             "camera_model: pinhole\n"
             "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
             "distortion_model: radial-tangential\n"
             "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n");
  WriteInput(kEurocFolder + "/mav0/state_groundtruth_estimate0/data.csv",
             "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
             "q_RS_y [], q_RS_z []\n"
             "1403715273262142976,0.878612,2.142470,0.947262,0.060514,-0.828459,-0.058956,"
             "-0.553641\n");
  return ScratchDir() + "/" + kEurocFolder;
}

}  // namespace

void ReadEurocWithInput(const std::string& relative_file, const std::uint8_t* data,
                        std::size_t size) {
  const std::string root = ValidEurocFolder();
  WriteInput(kEurocFolder + "/" + relative_file, data, size);
  try {
    ReadEurocSequence(root);
  } catch (const ParseError&) {
  } catch (const FileError&) {
  } catch (const SettingsError&) {
  }
}

}  // namespace ocg::fuzz
