// StderrCapture (src/core/stderr_capture.h): what libraries print on
// descriptor 2 during a capture is returned and never reaches the stream;
// the stream is the same before and after, also when it was closed.
#include "core/stderr_capture.h"

#include "fss/core/error.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <plplot/plplot.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

// PLplot's warning function (plplotP.h, its private header; exported by the library).
extern "C" void plwarn(PLCHAR_VECTOR message);

namespace fss::detail {
namespace {

TEST(StderrCapture, KeepsEveryWriterOffTheStream) {
  testing::internal::CaptureStderr();
  std::string captured;
  {
    StderrCapture capture;
    std::fprintf(stderr, "stdio\n");
    std::cerr << "iostream\n";
    const char raw[] = "write(2)\n";
    EXPECT_EQ(write(STDERR_FILENO, raw, sizeof raw - 1), static_cast<ssize_t>(sizeof raw - 1));
    plwarn("a PLplot warning");  // PLplot prints its warnings with fprintf(stderr)
    captured = capture.Finish();
    EXPECT_EQ(capture.Finish(), "");  // once only
  }
  std::fprintf(stderr, "after\n");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "after\n");
  EXPECT_NE(captured.find("stdio\niostream\nwrite(2)\n"), std::string::npos) << captured;
  EXPECT_NE(captured.find("*** PLPLOT WARNING ***\na PLplot warning\n"), std::string::npos)
      << captured;
}

TEST(StderrCapture, WriteStderrWaitsForTheCaptureToEnd) {
  // A warning written from another thread while a picture is drawn must
  // reach stderr, not the capture (it once failed the plot with its text).
  testing::internal::CaptureStderr();
  std::string captured;
  std::thread writer;
  {
    StderrCapture capture;
    writer = std::thread([] { fss::write_stderr("fssim: warning: from another thread\n"); });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the writer waits meanwhile
    std::fprintf(stderr, "library\n");
    captured = capture.Finish();
  }
  writer.join();
  EXPECT_EQ(captured, "library\n");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "fssim: warning: from another thread\n");
}

TEST(StderrCapture, DestructorPutsTheStreamBack) {
  testing::internal::CaptureStderr();
  {
    const StderrCapture capture;
    std::fprintf(stderr, "dropped\n");
  }
  std::fprintf(stderr, "kept\n");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "kept\n");
}

TEST(StderrCapture, AClosedStreamStaysClosed) {
  // In a child: close descriptor 2, capture, and check that 2 is closed again
  // and that the capture got the text. Exit status 0 means all held.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(STDERR_FILENO);
    std::string text;
    {
      StderrCapture capture;
      if (write(STDERR_FILENO, "x", 1) != 1) _exit(3);
      text = capture.Finish();
    }
    const bool closed = fcntl(STDERR_FILENO, F_GETFD) == -1 && errno == EBADF;
    _exit(text == "x" ? (closed ? 0 : 2) : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: text not captured, 2: descriptor 2 left open";
}

}  // namespace
}  // namespace fss::detail
