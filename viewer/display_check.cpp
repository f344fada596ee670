#include "viewer/display_check.h"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include "core/error.h"

namespace acpca {

namespace {

bool connects(int domain, const sockaddr* address, socklen_t length) {
  const int fd = ::socket(domain, SOCK_STREAM, 0);
  if (fd < 0) return false;
  const bool ok = ::connect(fd, address, length) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

std::string displayProblem() {
  const char* qpa = std::getenv("QT_QPA_PLATFORM");
  if (qpa && std::strcmp(qpa, "offscreen") == 0) return "";  // headless on purpose
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    return "no display: DISPLAY is not set. Run it on a desktop, over ssh -X, or under "
           "xvfb-run";
  // DISPLAY is [host]:number[.screen].
  const std::string text = display;
  const auto colon = text.rfind(':');
  const std::string host = colon == std::string::npos ? "" : text.substr(0, colon);
  const std::string number = text.substr(colon == std::string::npos ? 0 : colon + 1);
  const std::string server = number.substr(0, number.find('.'));
  const std::string unreachable =
      concat("no display: nothing answers at DISPLAY='", text, "' (is the X server running?)");
  if (server.empty() || server.find_first_not_of("0123456789") != std::string::npos)
    return concat("no display: cannot read DISPLAY='", text, "'");
  if (host.empty() || host == "unix") {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string socketPath = "/tmp/.X11-unix/X" + server;
    std::strncpy(address.sun_path, socketPath.c_str(), sizeof address.sun_path - 1);
    if (connects(AF_UNIX, reinterpret_cast<sockaddr*>(&address), sizeof address)) return "";
    if (host == "unix") return unreachable;
  }
  addrinfo hints{}, *found = nullptr;
  hints.ai_socktype = SOCK_STREAM;
  const std::string port = std::to_string(6000 + std::stoi(server));
  if (::getaddrinfo(host.empty() ? "localhost" : host.c_str(), port.c_str(), &hints, &found) != 0)
    return unreachable;
  bool ok = false;
  for (addrinfo* a = found; a && !ok; a = a->ai_next)
    ok = connects(a->ai_family, a->ai_addr, a->ai_addrlen);
  ::freeaddrinfo(found);
  return ok ? "" : unreachable;
}

}  // namespace acpca
