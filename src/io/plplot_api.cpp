// PLplot loaded at the first picture: dlopen of the SONAME the build compiled against
// (FSS_PLPLOT_SONAME, CMakeLists.txt) and one dlsym a function.
#include "io/plplot_api.h"

#include <dlfcn.h>

#include <string>
#include <type_traits>

#include "fss/core/error.h"

namespace fss::plotting {
namespace {

// The one-line error of a picture that cannot be drawn for want of PLplot: what the dynamic
// loader said and what to install.
[[noreturn]] void refuse_missing_plplot(const char* loader_message) {
  throw_runtime_error(std::string("cannot draw plots: cannot load PLplot: ") +
                      (loader_message ? loader_message : FSS_PLPLOT_SONAME) +
                      " (install the Debian packages " FSS_PLPLOT_PACKAGE
                      " and plplot-driver-cairo, or run with --no-plots)");
}

// Opens the library (kept open for the life of the process: PLplot holds global state and its
// drivers link against it) and finds every function of FSS_PLPLOT_FUNCTIONS. RTLD_LOCAL: its
// symbols resolve nothing else in the process.
PlplotApi load_plplot() {
  void* library = ::dlopen(FSS_PLPLOT_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr) refuse_missing_plplot(::dlerror());
  PlplotApi api;
  const auto find = [library](auto& member, const char* symbol) {
    ::dlerror();
    void* address = ::dlsym(library, symbol);
    const char* failure = ::dlerror();
    if (address == nullptr || failure != nullptr) {
      const std::string message = failure ? failure : std::string(symbol) + " is null";
      ::dlclose(library);
      refuse_missing_plplot(message.c_str());
    }
    member = reinterpret_cast<std::remove_reference_t<decltype(member)>>(address);
  };
#define FSS_PLPLOT_FIND(member, symbol) find(api.member, #symbol);
  FSS_PLPLOT_FUNCTIONS(FSS_PLPLOT_FIND)
#undef FSS_PLPLOT_FIND
  return api;
}

}  // namespace

// Loads once, thread-safe; a failed load throws and is tried again at the next call.
const PlplotApi& plplot_api() {
  static const PlplotApi api = load_plplot();
  return api;
}

}  // namespace fss::plotting
