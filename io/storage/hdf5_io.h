#pragma once
// Reading and writing the few kinds of HDF5 objects storage uses: groups, scalar and 1-D numeric
// attributes, strings (attributes or datasets) and float64 datasets. Every object is created
// without modification times, so identical content gives identical files. Failures throw
// std::runtime_error naming the object (the caller adds the file path, see h5::with_context).
#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "io/storage/hdf5_handles.h"

namespace lbsolid::server::storage::h5 {

// --- property lists ---------------------------------------------------------------------------

inline PropertyList untimed(hid_t property_class, const std::string& what) {
  PropertyList list(check(H5Pcreate(property_class), "cannot create " + what + " property list"));
  check_status(H5Pset_obj_track_times(list.get(), 0), "cannot turn off time tracking");
  return list;
}
// The file creation list also creates the root group, so it carries the setting too.
inline PropertyList file_creation() { return untimed(H5P_FILE_CREATE, "file creation"); }
inline PropertyList group_creation() { return untimed(H5P_GROUP_CREATE, "group creation"); }
inline PropertyList dataset_creation() { return untimed(H5P_DATASET_CREATE, "dataset creation"); }

// The 1.8 object header format: readable by every HDF5 since 1.8 and able to hold attributes over
// 64 KiB (a long scenario text), which the default earliest format cannot.
inline PropertyList file_access_v18() {
  PropertyList list(check(H5Pcreate(H5P_FILE_ACCESS), "cannot create file access property list"));
  check_status(H5Pset_libver_bounds(list.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST), "cannot set format bounds");
  return list;
}

// --- groups and links -------------------------------------------------------------------------

inline bool has_link(hid_t location, const std::string& name) {
  const htri_t exists = H5Lexists(location, name.c_str(), H5P_DEFAULT);
  check_status(exists < 0 ? -1 : 0, "cannot look up " + name);
  return exists > 0;
}

inline Group create_group(hid_t location, const std::string& name) {
  const PropertyList creation = group_creation();
  return Group(check(H5Gcreate2(location, name.c_str(), H5P_DEFAULT, creation.get(), H5P_DEFAULT),
                     "cannot create group " + name));
}

inline Group open_group(hid_t location, const std::string& name) {
  return Group(check(H5Gopen2(location, name.c_str(), H5P_DEFAULT), "cannot open group " + name));
}

inline Group open_or_create_group(hid_t location, const std::string& name) {
  return has_link(location, name) ? open_group(location, name) : create_group(location, name);
}

// --- numeric types ----------------------------------------------------------------------------

// In memory: the native type; in the file: a fixed little-endian type whatever the machine.
template <class T>
struct NumberType;
template <>
struct NumberType<int> {
  static hid_t memory() { return H5T_NATIVE_INT; }
  static hid_t file() { return H5T_STD_I32LE; }
};
template <>
struct NumberType<long> {
  static hid_t memory() { return H5T_NATIVE_LONG; }
  static hid_t file() { return H5T_STD_I64LE; }
};
template <>
struct NumberType<double> {
  static hid_t memory() { return H5T_NATIVE_DOUBLE; }
  static hid_t file() { return H5T_IEEE_F64LE; }
};

inline Dataspace simple_space(const std::vector<hsize_t>& dims, const std::vector<hsize_t>& max_dims = {}) {
  return Dataspace(check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(),
                                          max_dims.empty() ? nullptr : max_dims.data()),
                         "cannot create dataspace"));
}

inline std::vector<hsize_t> extent_of(hid_t space) {
  const int rank = H5Sget_simple_extent_ndims(space);
  check_status(rank < 0 ? -1 : 0, "cannot read dataspace rank");
  std::vector<hsize_t> dims(rank);
  check_status(H5Sget_simple_extent_dims(space, dims.data(), nullptr), "cannot read dataspace extent");
  return dims;
}

inline hsize_t element_count(const std::vector<hsize_t>& dims) {
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  return count;
}

// --- numeric attributes -----------------------------------------------------------------------

template <class T>
void write_attribute(hid_t object, const std::string& name, const std::vector<T>& values) {
  const Dataspace space = simple_space({values.size()});
  const Attribute attribute(check(H5Acreate2(object, name.c_str(), NumberType<T>::file(), space.get(), H5P_DEFAULT,
                                             H5P_DEFAULT),
                                  "cannot create attribute " + name));
  check_status(H5Awrite(attribute.get(), NumberType<T>::memory(), values.data()), "cannot write attribute " + name);
}

template <class T>
void write_attribute(hid_t object, const std::string& name, T value) {
  const Dataspace space(check(H5Screate(H5S_SCALAR), "cannot create dataspace"));
  const Attribute attribute(check(H5Acreate2(object, name.c_str(), NumberType<T>::file(), space.get(), H5P_DEFAULT,
                                             H5P_DEFAULT),
                                  "cannot create attribute " + name));
  check_status(H5Awrite(attribute.get(), NumberType<T>::memory(), &value), "cannot write attribute " + name);
}

template <class T>
std::vector<T> read_attribute_values(hid_t object, const std::string& name) {
  const Attribute attribute(check(H5Aopen(object, name.c_str(), H5P_DEFAULT), "missing attribute " + name));
  const Dataspace space(check(H5Aget_space(attribute.get()), "cannot read attribute " + name));
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  check_status(count < 0 ? -1 : 0, "cannot read attribute " + name);
  const Datatype type(check(H5Aget_type(attribute.get()), "cannot read attribute " + name));
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_INTEGER && type_class != H5T_FLOAT)
    throw std::runtime_error("attribute " + name + " is not a number");
  std::vector<T> values(count);
  check_status(H5Aread(attribute.get(), NumberType<T>::memory(), values.data()), "cannot read attribute " + name);
  return values;
}

template <class T>
T read_attribute(hid_t object, const std::string& name) {
  const std::vector<T> values = read_attribute_values<T>(object, name);
  if (values.size() != 1)
    throw std::runtime_error("attribute " + name + " holds " + std::to_string(values.size()) + " values, expected 1");
  return values[0];
}

// --- strings ----------------------------------------------------------------------------------

// Fixed-length, null-padded and exactly as long as the text: every byte round-trips (newlines,
// even NULs) and no terminator is added. An empty text has a null dataspace (HDF5 has no
// zero-length string type).
inline Datatype fixed_string_type(std::size_t length) {
  Datatype type(check(H5Tcopy(H5T_C_S1), "cannot create string type"));
  check_status(H5Tset_size(type.get(), std::max<std::size_t>(length, 1)), "cannot size string type");
  check_status(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "cannot pad string type");
  check_status(H5Tset_cset(type.get(), H5T_CSET_UTF8), "cannot set string character set");
  return type;
}

inline Dataspace string_space(const std::string& text) {
  return Dataspace(check(H5Screate(text.empty() ? H5S_NULL : H5S_SCALAR), "cannot create dataspace"));
}

inline void write_string_attribute(hid_t object, const std::string& name, const std::string& text) {
  const Datatype type = fixed_string_type(text.size());
  const Dataspace space = string_space(text);
  const Attribute attribute(check(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                                  "cannot create attribute " + name));
  if (!text.empty())
    check_status(H5Awrite(attribute.get(), type.get(), text.data()), "cannot write attribute " + name);
}

// A 1-D attribute of strings (H5MD's box boundary), padded to the longest.
inline void write_string_array_attribute(hid_t object, const std::string& name, const std::vector<std::string>& texts) {
  std::size_t width = 1;
  for (const std::string& t : texts) width = std::max(width, t.size());
  std::string packed(width * texts.size(), '\0');
  for (std::size_t i = 0; i < texts.size(); ++i)
    std::memcpy(packed.data() + i * width, texts[i].data(), texts[i].size());
  const Datatype type = fixed_string_type(width);
  const Dataspace space = simple_space({texts.size()});
  const Attribute attribute(check(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                                  "cannot create attribute " + name));
  check_status(H5Awrite(attribute.get(), type.get(), packed.data()), "cannot write attribute " + name);
}

inline void write_string_dataset(hid_t location, const std::string& name, const std::string& text) {
  const Datatype type = fixed_string_type(text.size());
  const Dataspace space = string_space(text);
  const PropertyList creation = dataset_creation();
  const Dataset dataset(check(H5Dcreate2(location, name.c_str(), type.get(), space.get(), H5P_DEFAULT, creation.get(),
                                         H5P_DEFAULT),
                              "cannot create dataset " + name));
  if (!text.empty())
    check_status(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()),
                 "cannot write dataset " + name);
}

// Reads a scalar string of any HDF5 flavour (ours, or variable-length as h5py writes them).
// read(memory_type, buffer) performs the H5Aread or H5Dread.
inline std::string read_string(hid_t file_type, hid_t space, const std::string& name,
                               const std::function<herr_t(hid_t, void*)>& read) {
  if (H5Tget_class(file_type) != H5T_STRING) throw std::runtime_error(name + " is not a string");
  if (H5Sget_simple_extent_type(space) == H5S_NULL) return "";
  if (H5Sget_simple_extent_npoints(space) != 1) throw std::runtime_error(name + " is not a single string");
  if (H5Tis_variable_str(file_type) > 0) {
    Datatype memory(check(H5Tcopy(H5T_C_S1), "cannot create string type"));
    check_status(H5Tset_size(memory.get(), H5T_VARIABLE), "cannot size string type");
    char* text = nullptr;
    check_status(read(memory.get(), &text), "cannot read " + name);
    std::string result = text != nullptr ? text : "";
    H5free_memory(text);
    return result;
  }
  const std::size_t length = H5Tget_size(file_type);
  Datatype memory = fixed_string_type(length);
  std::string result(length, '\0');
  check_status(read(memory.get(), result.data()), "cannot read " + name);
  // Other writers' null-terminated strings end at the first NUL; ours are exact.
  if (H5Tget_strpad(file_type) == H5T_STR_NULLTERM) result.resize(std::strlen(result.c_str()));
  return result;
}

inline std::string read_string_attribute(hid_t object, const std::string& name) {
  const Attribute attribute(check(H5Aopen(object, name.c_str(), H5P_DEFAULT), "missing attribute " + name));
  const Datatype type(check(H5Aget_type(attribute.get()), "cannot read attribute " + name));
  const Dataspace space(check(H5Aget_space(attribute.get()), "cannot read attribute " + name));
  return read_string(type.get(), space.get(), "attribute " + name,
                     [&](hid_t memory, void* buffer) { return H5Aread(attribute.get(), memory, buffer); });
}

inline std::string read_string_dataset(hid_t location, const std::string& name) {
  const Dataset dataset(check(H5Dopen2(location, name.c_str(), H5P_DEFAULT), "missing dataset " + name));
  const Datatype type(check(H5Dget_type(dataset.get()), "cannot read dataset " + name));
  const Dataspace space(check(H5Dget_space(dataset.get()), "cannot read dataset " + name));
  return read_string(type.get(), space.get(), "dataset " + name, [&](hid_t memory, void* buffer) {
    return H5Dread(dataset.get(), memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
  });
}

// --- numeric datasets -------------------------------------------------------------------------

template <class T>
void write_dataset(hid_t location, const std::string& name, const std::vector<hsize_t>& dims, const T* values) {
  const Dataspace space = simple_space(dims);
  const PropertyList creation = dataset_creation();
  const Dataset dataset(check(H5Dcreate2(location, name.c_str(), NumberType<T>::file(), space.get(), H5P_DEFAULT,
                                         creation.get(), H5P_DEFAULT),
                              "cannot create dataset " + name));
  if (element_count(dims) > 0)
    check_status(H5Dwrite(dataset.get(), NumberType<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values),
                 "cannot write dataset " + name);
}

template <class T>
struct DatasetValues {
  std::vector<hsize_t> dims;
  std::vector<T> values;  // C order
};

// More than max_values is refused before anything is allocated: a damaged extent must not ask
// for terabytes.
template <class T>
DatasetValues<T> read_dataset(hid_t location, const std::string& name,
                              hsize_t max_values = std::numeric_limits<hsize_t>::max()) {
  const Dataset dataset(check(H5Dopen2(location, name.c_str(), H5P_DEFAULT), "missing dataset " + name));
  const Dataspace space(check(H5Dget_space(dataset.get()), "cannot read dataset " + name));
  const Datatype type(check(H5Dget_type(dataset.get()), "cannot read dataset " + name));
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_INTEGER && type_class != H5T_FLOAT)
    throw std::runtime_error("dataset " + name + " is not numeric");
  DatasetValues<T> result;
  result.dims = extent_of(space.get());
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  check_status(count < 0 ? -1 : 0, "cannot read dataset " + name);
  if (static_cast<hsize_t>(count) > max_values)
    throw std::runtime_error("dataset " + name + " claims " + std::to_string(count) + " values, more than the " +
                             std::to_string(max_values) + " the file can hold");
  result.values.resize(static_cast<std::size_t>(count));
  if (!result.values.empty())
    check_status(H5Dread(dataset.get(), NumberType<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, result.values.data()),
                 "cannot read dataset " + name);
  return result;
}

}  // namespace lbsolid::server::storage::h5
