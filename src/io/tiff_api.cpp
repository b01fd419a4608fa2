// libtiff loaded at the first TIFF read or written: dlopen of the SONAME the build compiled
// against (FSS_TIFF_SONAME, CMakeLists.txt) and one dlsym a function.
#include "io/tiff_api.h"

#include <dlfcn.h>

#include <string>
#include <type_traits>

#include "fss/core/error.h"

namespace fss {
namespace {

[[noreturn]] void refuse_missing_libtiff(const std::string& loader_message) {
  throw_runtime_error("cannot load libtiff: " + loader_message +
                      " (install the Debian package " FSS_TIFF_PACKAGE ")");
}

// Opens the library (kept open for the life of the process) and finds every function of
// FSS_TIFF_FUNCTIONS. RTLD_LOCAL: its symbols resolve nothing else in the process.
TiffApi load_libtiff() {
  void* library = ::dlopen(FSS_TIFF_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr) {
    const char* failure = ::dlerror();
    refuse_missing_libtiff(failure ? failure : FSS_TIFF_SONAME);
  }
  TiffApi api;
  const auto find = [library](auto& member, const char* symbol) {
    ::dlerror();
    void* address = ::dlsym(library, symbol);
    const char* failure = ::dlerror();
    if (address == nullptr || failure != nullptr) {
      const std::string message = failure ? failure : std::string(symbol) + " is null";
      ::dlclose(library);
      refuse_missing_libtiff(message);
    }
    member = reinterpret_cast<std::remove_reference_t<decltype(member)>>(address);
  };
#define FSS_TIFF_FIND(member) find(api.member, "TIFF" #member);
  FSS_TIFF_FUNCTIONS(FSS_TIFF_FIND)
#undef FSS_TIFF_FIND
  return api;
}

}  // namespace

// Loads once, thread-safe; a failed load throws and is tried again at the next call.
const TiffApi& tiff_api() {
  static const TiffApi api = load_libtiff();
  return api;
}

}  // namespace fss
