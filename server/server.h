#pragma once
// The TCP side of `vts serve` (docs/PROTOCOL.md): one thread, poll(), every
// client's input split into lines and answered by the CellHost in order, its
// output queued and written as the socket takes it. A client whose queue
// passes the limit (it does not read) is dropped; a line over the limit ends
// its connection after the error answer; nothing a client sends can stop
// the others from being served.
#include <cstddef>
#include <cstdint>
#include <string>

#include "server/host.h"

namespace vts::server {

struct ServerOptions {
  std::string address = "127.0.0.1";
  int port = 5170;  // 0: any free port (port() says which)
  // Any address but loopback needs this (docs/PROTOCOL.md, "Security").
  bool allow_remote = false;
  int max_clients = 256;
  std::size_t max_queue_bytes = std::size_t{16} << 20;  // per client
};

struct ServerStats {
  std::int64_t accepted = 0;
  std::int64_t refused = 0;       // over max_clients
  std::int64_t dropped_slow = 0;  // queue over the limit
  std::int64_t too_long = 0;      // a line over the limit
  std::int64_t lines = 0;         // requests answered
  std::int64_t pushed = 0;        // pushes queued (events, profiles, joints)
  std::size_t max_queue = 0;      // the largest queue seen (bytes)
  int clients = 0;                // connected now
};

class Server {
 public:
  // Binds and listens; throws std::invalid_argument for a bad or non-local
  // address without allow_remote, std::runtime_error naming the address when
  // the socket cannot be bound.
  Server(CellHost& host, const ServerOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const { return port_; }
  const std::string& address() const { return options_.address; }
  // Serves until stop(). In real time the host is advanced at its sensor's
  // rate by the wall clock from the first call.
  void run();
  // From any thread or a signal handler (async-signal-safe).
  void stop();
  ServerStats stats() const;

 private:
  struct Client;
  void accept_clients();
  void read_client(Client& c);
  void write_client(Client& c);
  void queue(Client& c, const std::string& line);

  CellHost& host_;
  ServerOptions options_;
  int listen_fd_ = -1;
  int wake_[2] = {-1, -1};
  int port_ = 0;
  int next_id_ = 1;
  struct Clients;
  Clients* clients_;
  ServerStats stats_;
};

}  // namespace vts::server
