// Movies of a folder of PNG frames: ffmpeg (H.264 MP4) when it is on PATH, else VTK's Ogg
// Theora writer.
#include <fmt/format.h>

#include "atomic_file.hpp"
#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/render.hpp"

#if STRATA_WITH_RENDER
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkNew.h>
#include <vtkOggTheoraWriter.h>
#include <vtkPNGReader.h>

#include <cstdlib>
#include <sstream>
#endif

namespace strata::io {
namespace fs = std::filesystem;

#if STRATA_WITH_RENDER
namespace {

// ffmpeg on PATH, or "".
std::string find_ffmpeg() {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(ss, dir, ':');) {
    const std::string full = (dir.empty() ? std::string(".") : dir) + "/ffmpeg";
    struct stat st {};
    if (::stat(full.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(full.c_str(), X_OK) == 0)
      return full;
  }
  return {};
}

// H.264 through ffmpeg; false (logged) when ffmpeg fails.
bool ffmpeg_movie(const std::string& ffmpeg, const fs::path& png_dir, const fs::path& mp4, int fps) {
  const auto tmp = fs::path(mp4.string() + ".tmp");
  const std::string pattern = (png_dir / "frame_%06d.png").string(), rate = std::to_string(fps);
  std::vector<std::string> args = {ffmpeg,
                                   "-nostdin",
                                   "-y",
                                   "-loglevel",
                                   "error",
                                   "-framerate",
                                   rate,
                                   "-i",
                                   pattern,
                                   "-vf",
                                   "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                   "-c:v",
                                   "libx264",
                                   "-pix_fmt",
                                   "yuv420p",
                                   "-movflags",
                                   "+faststart",
                                   "-f",
                                   "mp4",
                                   tmp.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  STRATA_CHECK(pid >= 0, IO, "fork for ffmpeg failed");
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(tmp)) {
    std::error_code ec;
    fs::remove(tmp, ec);
    log::warn("ffmpeg failed (status {}); no movie {}, the PNG frames are kept in {}", status, mp4.string(),
              png_dir.string());
    return false;
  }
  detail::commit(tmp, mp4);
  return true;
}

// Ogg Theora through VTK, frame by frame: the frames are read one at a time, so a long
// series costs the memory of one picture. Their sizes are checked from the PNG headers
// before anything is written.
void theora_movie(const fs::path& png_dir, const fs::path& ogv, int fps) {
  std::vector<fs::path> pngs;
  for (int k = 0;; ++k) {
    fs::path png = png_dir / fmt::format("frame_{:06d}.png", k);
    if (!fs::exists(png)) break;
    pngs.push_back(std::move(png));
  }
  vtkNew<vtkPNGReader> reader;
  auto size_of = [&](const fs::path& png) {
    reader->SetFileName(png.c_str());
    reader->UpdateInformation();
    int ext[6];
    reader->GetDataExtent(ext);
    return std::array<int, 2>{ext[1] - ext[0] + 1, ext[3] - ext[2] + 1};
  };
  const std::array<int, 2> size = size_of(pngs.front());
  for (const fs::path& png : pngs) {
    const std::array<int, 2> s = size_of(png);
    STRATA_CHECK(s == size, IO,
                 "make_movie: {} is {} x {} pixels, the first frame {} x {}: a movie's frames share one size",
                 png.string(), s[0], s[1], size[0], size[1]);
  }
  const auto tmp = fs::path(ogv.string() + ".tmp");
  try {
    vtkNew<vtkOggTheoraWriter> writer;
    writer->SetInputConnection(reader->GetOutputPort());
    writer->SetFileName(tmp.c_str());
    writer->SetRate(fps);
    writer->SetQuality(2);      // the highest of VTK's three: crack lines stay sharp
    writer->SetSubsampling(1);  // 4:2:0, what every Theora player decodes (and a third faster)
    reader->SetFileName(pngs.front().c_str());
    writer->Start();
    for (const fs::path& png : pngs) {
      reader->SetFileName(png.c_str());
      writer->Write();
      STRATA_CHECK(writer->GetError() == 0, IO, "make_movie: the Theora encoder failed on {}", png.string());
    }
    writer->End();
    STRATA_CHECK(fs::exists(tmp), IO, "make_movie: the Theora encoder wrote no {}", tmp.string());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  detail::commit(tmp, ogv);
}

}  // namespace

fs::path make_movie(const fs::path& png_dir, const fs::path& stem, int fps) {
  STRATA_CHECK(fs::exists(png_dir / "frame_000000.png"), IO, "make_movie: no {}",
               (png_dir / "frame_000000.png").string());
  STRATA_CHECK(fps >= 1 && fps <= 1000, Input, "make_movie: {} frames per second must be in [1, 1000]", fps);
  detail::make_parent(stem);
  const std::string ffmpeg = find_ffmpeg();
  fs::path movie = stem;
  if (!ffmpeg.empty()) {
    movie.replace_extension(".mp4");
    if (!ffmpeg_movie(ffmpeg, png_dir, movie, fps)) return {};
  } else {
    movie.replace_extension(".ogv");
    theora_movie(png_dir, movie, fps);
  }
  log::info("wrote movie {}", movie.string());
  return movie;
}

#else  // !STRATA_WITH_RENDER

fs::path make_movie(const fs::path&, const fs::path&, int) {
  fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures");
}

#endif

}  // namespace strata::io
