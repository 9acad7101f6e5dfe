// C++ errors become Python exceptions with the same message: the file, line and key it
// names are what the user acts on. std::invalid_argument (options, alignment) is
// pybind11's ValueError already.

#include "bindings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/text_lines.h"
#include "ocg/ocg/replay_format.h"

namespace ocg::python {

void BindErrors(pybind11::module_& module) {
  pybind11::register_exception<FileError>(module, "FileError", PyExc_OSError);
  pybind11::register_exception<ParseError>(module, "ParseError", PyExc_ValueError);
  pybind11::register_exception<SettingsError>(module, "SettingsError", PyExc_ValueError);
  pybind11::register_exception<ReplayFormatError>(module, "ReplayFormatError", PyExc_ValueError);
}

}  // namespace ocg::python
