#pragma once
// Owning wrappers for HDF5 identifiers (hid_t) and the conversion of HDF5 failures into
// std::runtime_error. Private to io/storage: the public headers never expose hdf5.h.
#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace lbsolid::server::storage::h5 {

// One open HDF5 object, closed by Close when the wrapper goes out of scope. close() reports the
// result where it matters (closing a file writes its metadata); the destructor cannot.
template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { close(); }
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      close();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  herr_t close() { return id_ >= 0 ? Close(std::exchange(id_, H5I_INVALID_HID)) : 0; }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using File = Handle<H5Fclose>;
using Group = Handle<H5Gclose>;
using Dataset = Handle<H5Dclose>;
using Dataspace = Handle<H5Sclose>;
using Datatype = Handle<H5Tclose>;  // only for types we created (H5Tcopy, H5Aget_type, ...)
using Attribute = Handle<H5Aclose>;
using PropertyList = Handle<H5Pclose>;

// The innermost message on this thread's HDF5 error stack (the lowest layer says most, e.g.
// "errno = 2, error message = 'No such file or directory'"), and clears the stack.
inline std::string take_error_cause() {
  std::string cause;
  const H5E_walk2_t innermost = [](unsigned n, const H5E_error2_t* error, void* out) -> herr_t {
    if (n == 0 && error->desc != nullptr) *static_cast<std::string*>(out) = error->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, &cause);
  H5Eclear2(H5E_DEFAULT);
  return cause;
}

[[noreturn]] inline void fail(const std::string& what) {
  const std::string cause = take_error_cause();
  throw std::runtime_error(cause.empty() ? what : what + " (" + cause + ")");
}

// An HDF5 call's result, or an exception saying what failed and why.
inline hid_t check(hid_t id, const std::string& what) {
  if (id < 0) fail(what);
  return id;
}
inline void check_status(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

// While alive, HDF5 does not print its error stack to stderr on this thread (the stack is turned
// into exceptions instead); the previous setting comes back afterwards, so code elsewhere in the
// process that relies on HDF5's printing keeps it.
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &previous_function_, &previous_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, previous_function_, previous_data_); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t previous_function_ = nullptr;
  void* previous_data_ = nullptr;
};

// Runs body; a std::runtime_error from it is re-thrown with `context` (which names the file) in
// front. Other exceptions (std::invalid_argument for bad input) pass through unchanged.
template <class Body>
auto with_context(const std::string& context, Body&& body) {
  QuietErrors quiet;
  try {
    return body();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(context + ": " + e.what());
  }
}

}  // namespace lbsolid::server::storage::h5
