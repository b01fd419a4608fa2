// The PLplot session of the plots: one stream per picture, drawn by the
// memcairo device over a caller-owned RGBA buffer, all of it under one
// process-wide mutex, with what the libraries print on stderr captured.
#include "io/plot_backend.h"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <string>
#include <string_view>

#include "core/stderr_capture.h"
#include "fss/core/error.h"

namespace fss::plotting {
namespace {

std::mutex g_plplot_mutex;
std::string* g_plplot_messages = nullptr;  // guarded by g_plplot_mutex

// PLplot reports recoverable errors through this handler (instead of printing
// them on stderr); they are turned into an fss::Error after the picture.
void collect_plplot_message(PLCHAR_VECTOR message) {
  if (g_plplot_messages == nullptr) return;
  if (!g_plplot_messages->empty()) *g_plplot_messages += "; ";
  *g_plplot_messages += message;
}

// PLplot calls exit() after this handler returns: throw instead, so that a
// fatal PLplot error becomes an fss::Error and not the end of the process
// (the exception unwinds through PLplot's C frames, which Debian builds with
// unwind tables). The stream is then ended by render().
int refuse_plplot_exit(PLCHAR_VECTOR message) {
  throw Error(ErrorKind::kRuntime, std::string("PLplot failed: ") + message);
}

bool memcairo_available() {
  constexpr int kCapacity = 256;
  PLCHAR_VECTOR menus[kCapacity];
  PLCHAR_VECTOR names[kCapacity];
  PLCHAR_VECTOR* menu_list = menus;
  PLCHAR_VECTOR* name_list = names;
  int count = kCapacity;
  plgDevs(&menu_list, &name_list, &count);
  for (int i = 0; i < count; ++i) {
    if (name_list[i] != nullptr && std::strcmp(name_list[i], "memcairo") == 0) return true;
  }
  return false;
}

// The RGB of each Colour (plot_backend.h).
constexpr PLINT kPalette[kPaletteSize][3] = {
    {255, 255, 255}, {34, 34, 34},   {175, 175, 175}, {31, 92, 170},   // background .. code
    {196, 214, 238}, {90, 90, 90},   {200, 30, 30},   {190, 20, 20},   // fill .. warning
    {31, 92, 170},   {214, 120, 20}, {40, 150, 60},   {150, 60, 170},  // series
    {20, 160, 180},  {200, 30, 30},  {140, 110, 40},  {110, 110, 110},
};

// What the libraries under PLplot printed during a picture, as one line:
// its non-empty lines joined by "; ", PLplot's "*** PLPLOT WARNING ***"
// banners left out, control characters escaped, at most about 400 bytes.
std::string library_output_line(std::string_view text) {
  std::string line;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find('\n'), text.size());
    std::string_view part = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    while (!part.empty() && (part.back() == '\r' || part.back() == ' ')) part.remove_suffix(1);
    if (part.empty() || part.find("*** PLPLOT") == 0) continue;
    if (!line.empty()) line += "; ";
    line += part;
  }
  constexpr std::size_t kMaxBytes = 400;
  if (line.size() > kMaxBytes) line = line.substr(0, kMaxBytes) + "...";
  return escape_control_characters(line);
}

// One PLplot stream drawing over `rgba` until the end of the scope.
class PlplotStream {
 public:
  PlplotStream(int width, int height, std::vector<std::uint8_t>& rgba) {
    plsabort(collect_plplot_message);
    plsexit(refuse_plplot_exit);
    plgstrm(&previous_);
    PLINT stream = 0;
    plmkstrm(&stream);
    if (stream < 0) throw_runtime_error("PLplot has no free stream");
    plsdev("memcairo");
    plsmema(width, height, rgba.data());
    plspause(0);
    plscmap0n(kPaletteSize);
    for (int i = 0; i < kPaletteSize; ++i) {
      plscol0(i, kPalette[i][0], kPalette[i][1], kPalette[i][2]);
    }
    plinit();
    pladv(0);
  }
  ~PlplotStream() {
    plend1();
    plsstrm(previous_);
  }
  PlplotStream(const PlplotStream&) = delete;
  PlplotStream& operator=(const PlplotStream&) = delete;

 private:
  PLINT previous_ = 0;
};

}  // namespace

std::array<int, 3> palette_rgb(PLINT colour) {
  const PLINT* rgb = kPalette[colour >= 0 && colour < kPaletteSize ? colour : kInk];
  return {rgb[0], rgb[1], rgb[2]};
}

void render(int width, int height, std::vector<std::uint8_t>& rgba,
            const std::function<void()>& draw) {
  std::lock_guard<std::mutex> lock(g_plplot_mutex);
  plplot_api();  // the first picture loads PLplot, or says why it cannot
  static const bool available = memcairo_available();
  if (!available) {
    throw_runtime_error(
        "cannot draw plots: PLplot's memcairo device is missing (install the Debian package "
        "plplot-driver-cairo, or run with --no-plots)");
  }
  std::string messages;
  struct Collect {
    explicit Collect(std::string* messages) { g_plplot_messages = messages; }
    ~Collect() { g_plplot_messages = nullptr; }
    Collect(const Collect&) = delete;
    Collect& operator=(const Collect&) = delete;
  } collect(&messages);
  detail::StderrCapture capture;
  {
    const PlplotStream stream(width, height, rgba);
    draw();
  }
  const std::string printed = library_output_line(capture.Finish());
  if (!printed.empty()) messages += (messages.empty() ? "" : "; ") + printed;
  if (!messages.empty()) throw_runtime_error("PLplot: " + messages);
}

std::vector<std::uint8_t> to_samples(const std::vector<std::uint8_t>& rgba, int channels) {
  const std::size_t pixels = rgba.size() / 4;
  std::vector<std::uint8_t> samples(pixels * static_cast<std::size_t>(channels));
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* pixel = &rgba[4 * i];
    if (channels == 1) {  // round(s / 3) = (s + 1) / 3 for s >= 0
      samples[i] = static_cast<std::uint8_t>((pixel[0] + pixel[1] + pixel[2] + 1) / 3);
    } else {
      std::copy(pixel, pixel + 3, &samples[3 * i]);
    }
  }
  return samples;
}

}  // namespace fss::plotting
