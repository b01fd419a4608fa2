// Private: keeps what a library prints on the standard error stream away from
// it (PLplot's warnings, GLib's and Pango's messages under the cairo driver).
#pragma once

#include <mutex>
#include <string>

namespace fss::detail {

extern std::mutex g_capture_mutex;

// While alive, file descriptor 2 is an anonymous in-memory file; Finish()
// puts the original stream back and returns what was written meanwhile (the
// destructor puts it back too). One capture at a time in the process: the
// constructor waits for the previous one to end. Writers of other threads
// that write to descriptor 2 during a capture are captured as well, except
// through fss::write_stderr, which waits for the capture to end.
// When no anonymous file can be made, nothing is captured.
class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Ends the capture and returns its bytes (empty after the first call);
  // write_stderr calls waiting for it go on then.
  std::string Finish();

 private:
  std::unique_lock<std::mutex> lock_;
  int saved_ = -1;     // duplicate of the original descriptor 2, -1 if it was closed
  int captured_ = -1;  // the anonymous file, -1 when not capturing
};

}  // namespace fss::detail
