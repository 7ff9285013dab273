#include "scenario_attribute.h"

#include <hdf5.h>

#include <stdexcept>
#include <vector>

namespace lbsolid::drag {
namespace {

// Closes an HDF5 id when it goes out of scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

}  // namespace

std::string read_scenario_attribute(const std::string& h5_path) {
  const std::string where = h5_path + ": /parameters scenario: ";
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported here, not printed by HDF5
  const Handle file(H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(h5_path + ": cannot open as HDF5");
  const Handle attribute(H5Aopen_by_name(file.get(), "/parameters", "scenario", H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.ok()) throw std::runtime_error(where + "missing");
  const Handle type(H5Aget_type(attribute.get()), H5Tclose);
  const Handle space(H5Aget_space(attribute.get()), H5Sclose);
  if (!type.ok() || !space.ok() || H5Tget_class(type.get()) != H5T_STRING)
    throw std::runtime_error(where + "not a string");
  if (H5Sget_simple_extent_type(space.get()) == H5S_NULL) return "";  // how an empty text is stored
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw std::runtime_error(where + "not a single string");

  if (H5Tis_variable_str(type.get()) > 0) {
    const Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memory.get(), H5T_VARIABLE);
    char* text = nullptr;
    if (H5Aread(attribute.get(), memory.get(), &text) < 0) throw std::runtime_error(where + "cannot read");
    std::string out = text ? text : "";
    H5free_memory(text);
    return out;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::vector<char> buffer(size);
  if (H5Aread(attribute.get(), type.get(), buffer.data()) < 0) throw std::runtime_error(where + "cannot read");
  std::string out(buffer.begin(), buffer.end());
  // Null-padded (or null-terminated): the text ends at its last non-NUL byte.
  const auto end = out.find_last_not_of('\0');
  out.resize(end == std::string::npos ? 0 : end + 1);
  return out;
}

}  // namespace lbsolid::drag
