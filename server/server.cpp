#include "server/server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <list>
#include <stdexcept>
#include <vector>

namespace vts::server {

struct Server::Client {
  int fd = -1;
  Peer peer;
  LineBuffer lines;
  std::string out;          // queued output
  std::size_t out_off = 0;  // written so far
  bool closing = false;     // stop reading; close once the output is written
  bool dead = false;        // close now
};

struct Server::Clients {
  std::list<Client> list;
};

namespace {

void set_nonblocking(int fd) { ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL, 0) | O_NONBLOCK); }

std::string errno_text() { return std::strerror(errno); }

}  // namespace

Server::Server(CellHost& host, const ServerOptions& options)
    : host_(host), options_(options), clients_(new Clients) {
  in_addr addr{};
  if (::inet_pton(AF_INET, options.address.c_str(), &addr) != 1)
    throw std::invalid_argument("--listen: '" + options.address + "' is not an IPv4 address (e.g. 127.0.0.1)");
  const bool loopback = (ntohl(addr.s_addr) >> 24) == 127;
  if (!loopback && !options.allow_remote)
    throw std::invalid_argument("--listen: '" + options.address +
                                "' is not a loopback address; binding it exposes the cell to the network "
                                "(docs/PROTOCOL.md, \"Security\"): add --allow-remote to do so");
  if (options.port < 0 || options.port > 65535)
    throw std::invalid_argument("--listen: port " + std::to_string(options.port) + " is out of range 0..65535");
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw std::runtime_error("socket: " + errno_text());
  const int one = 1;
  ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_addr = addr;
  sa.sin_port = htons(static_cast<std::uint16_t>(options.port));
  const std::string where = options.address + ":" + std::to_string(options.port);
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&sa), sizeof sa) != 0 || ::listen(listen_fd_, 64) != 0) {
    const std::string why = errno_text();
    ::close(listen_fd_);
    delete clients_;
    throw std::runtime_error("cannot listen on " + where + ": " + why);
  }
  socklen_t len = sizeof sa;
  ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &len);
  port_ = ntohs(sa.sin_port);
  set_nonblocking(listen_fd_);
  if (::pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0) {
    ::close(listen_fd_);
    delete clients_;
    throw std::runtime_error("pipe: " + errno_text());
  }
  host_.publish = [this](const Json& message, Topic topic) {
    std::string line;
    for (Client& c : clients_->list) {
      if (c.dead || c.closing || !c.peer.hello) continue;
      const bool wants = topic == Topic::Event ? c.peer.events : topic == Topic::Profile ? c.peer.profiles : c.peer.joints;
      if (!wants) continue;
      if (line.empty()) line = to_line(message);
      queue(c, line);
      ++stats_.pushed;
    }
  };
}

Server::~Server() {
  host_.publish = nullptr;
  for (Client& c : clients_->list) ::close(c.fd);
  delete clients_;
  if (listen_fd_ >= 0) ::close(listen_fd_);
  for (int fd : wake_)
    if (fd >= 0) ::close(fd);
}

void Server::stop() {
  const char b = 1;
  [[maybe_unused]] const auto n = ::write(wake_[1], &b, 1);
}

ServerStats Server::stats() const {
  ServerStats s = stats_;
  s.clients = static_cast<int>(clients_->list.size());
  return s;
}

void Server::queue(Client& c, const std::string& line) {
  if (c.dead) return;
  if (c.out.size() - c.out_off + line.size() > options_.max_queue_bytes) {
    // It does not read: holding more would grow without bound.
    c.dead = true;
    ++stats_.dropped_slow;
    return;
  }
  if (c.out_off > 0 && c.out_off >= c.out.size() / 2) {
    c.out.erase(0, c.out_off);
    c.out_off = 0;
  }
  c.out += line;
  stats_.max_queue = std::max(stats_.max_queue, c.out.size() - c.out_off);
}

void Server::accept_clients() {
  while (true) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN, or a connection that went away already
    if (static_cast<int>(clients_->list.size()) >= options_.max_clients) {
      static const char kFull[] =
          "{\"id\":null,\"ok\":false,\"error\":\"busy\",\"message\":\"too many clients\"}\n";
      [[maybe_unused]] const auto n = ::send(fd, kFull, sizeof kFull - 1, MSG_NOSIGNAL);
      ::close(fd);
      ++stats_.refused;
      continue;
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    Client& c = clients_->list.emplace_back();
    c.fd = fd;
    c.peer.id = next_id_++;
    ++stats_.accepted;
  }
}

void Server::read_client(Client& c) {
  char buf[65536];
  while (!c.dead && !c.closing) {
    const ssize_t n = ::recv(c.fd, buf, sizeof buf, 0);
    if (n == 0) {
      c.dead = true;  // the client closed; a half line it left is dropped
      return;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;
      return;
    }
    const bool framed = c.lines.feed(std::string_view(buf, static_cast<std::size_t>(n)), [&](std::string_view line) {
      if (c.dead || c.closing) return;
      if (line.find_first_not_of(" \t") == std::string_view::npos) return;  // blank
      ++stats_.lines;
      queue(c, to_line(host_.handle_line(line, c.peer)));
    });
    if (!framed) {
      ++stats_.too_long;
      queue(c, to_line(error_answer(nullptr, "too_long",
                                    "a line longer than " + std::to_string(kMaxLineBytes) +
                                        " bytes; the connection is closed")));
      c.closing = true;
      ::shutdown(c.fd, SHUT_RD);
    }
    if (static_cast<std::size_t>(n) < sizeof buf) return;
  }
}

void Server::write_client(Client& c) {
  while (!c.dead && c.out_off < c.out.size()) {
    const ssize_t n = ::send(c.fd, c.out.data() + c.out_off, c.out.size() - c.out_off, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;
      return;
    }
    c.out_off += static_cast<std::size_t>(n);
  }
  if (c.out_off == c.out.size()) {
    c.out.clear();
    c.out_off = 0;
    if (c.closing) c.dead = true;
  }
}

void Server::run() {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const double period = host_.realtime() ? 1.0 / host_.rate_hz() : 0.0;
  double next_tick = period;
  std::vector<pollfd> fds;
  std::vector<Client*> polled;
  while (true) {
    fds.clear();
    polled.clear();
    fds.push_back({wake_[0], POLLIN, 0});
    fds.push_back({listen_fd_, POLLIN, 0});
    for (Client& c : clients_->list) {
      short ev = c.closing ? 0 : POLLIN;
      if (c.out_off < c.out.size()) ev |= POLLOUT;
      fds.push_back({c.fd, ev, 0});
      polled.push_back(&c);
    }
    int timeout_ms = -1;
    if (period > 0.0) {
      const double now = std::chrono::duration<double>(Clock::now() - start).count();
      timeout_ms = std::max(0, static_cast<int>(std::ceil((next_tick - now) * 1000.0)));
    }
    const int n = ::poll(fds.data(), fds.size(), timeout_ms);
    if (n < 0 && errno != EINTR) throw std::runtime_error("poll: " + errno_text());
    if (n > 0 && (fds[0].revents & POLLIN)) return;  // stop()
    if (n > 0 && (fds[1].revents & POLLIN)) accept_clients();
    for (std::size_t i = 0; n > 0 && i < polled.size(); ++i) {
      Client& c = *polled[i];
      const short re = fds[i + 2].revents;
      if (re & (POLLIN | POLLHUP | POLLERR)) read_client(c);
      if (re & POLLNVAL) c.dead = true;
    }
    if (period > 0.0) {
      const double now = std::chrono::duration<double>(Clock::now() - start).count();
      if (now >= next_tick) {
        host_.advance_to(now);
        next_tick = (std::floor(now / period) + 1.0) * period;
      }
    }
    for (Client& c : clients_->list) write_client(c);
    for (auto it = clients_->list.begin(); it != clients_->list.end();) {
      if (!it->dead) {
        ++it;
        continue;
      }
      host_.disconnected(it->peer);
      ::close(it->fd);
      it = clients_->list.erase(it);
    }
  }
}

}  // namespace vts::server
