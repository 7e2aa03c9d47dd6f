#pragma once
/// An X display for off-screen rendering on a headless machine.
///
/// Debian's VTK has no OSMesa/EGL, so even off-screen render windows need an X server.
#include <string>

namespace strata::io {

/// Makes sure $DISPLAY names a usable X server and returns it.
///
/// If $DISPLAY is set and an X connection to it opens, nothing is done. Otherwise starts
/// `Xvfb -displayfd <fd> -screen 0 1600x1200x24 -nolisten tcp` (Xvfb picks a free display
/// number itself, so processes running in parallel never collide), waits until it is
/// ready, sets $DISPLAY and stops the server at process exit. The server also dies with
/// the thread that started it (PR_SET_PDEATHSIG), so call this from the main thread.
/// Never reads stdin. Thread-safe and idempotent.
/// Throws strata::Error (Unsupported) naming the package `xvfb` when Xvfb is not
/// installed, and (IO) when it does not come up within 20 s.
std::string ensure_display();

/// True when the X display named by $DISPLAY accepts a connection.
bool display_usable();

}  // namespace strata::io
