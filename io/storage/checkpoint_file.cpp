// A checkpoint is checked (checkpoint_validation.h), written in its layout (checkpoint_layout.h)
// into a temporary file of its own, and renamed over the target; reading verifies every checksum
// and checks the contents again.
#include "io/storage/checkpoint_file.h"

#include "io/storage/checkpoint_layout.h"
#include "io/storage/checkpoint_validation.h"
#include "io/storage/file_replace.h"
#include "io/storage/hdf5_handles.h"

namespace lbsolid::server::storage {

void write_checkpoint(const std::string& path, const CheckpointContents& contents, const WriterInfo& writer) {
  h5::with_context("cannot write checkpoint " + path, [&] {
    check_checkpoint_contents(contents);  // before anything is written: a bad state never replaces a good file
    TemporaryFile temporary(path);        // removed on failure: the target is then untouched
    temporary.close_descriptor();         // HDF5 writes it by name
    write_checkpoint_layout(temporary.path(), contents, writer);
    temporary.replace_target();
  });
}

CheckpointContents read_checkpoint(const std::string& path) {
  return h5::with_context("cannot read checkpoint " + path, [&] {
    CheckpointContents contents = read_checkpoint_layout(path);
    check_checkpoint_contents(contents);
    return contents;
  });
}

}  // namespace lbsolid::server::storage
