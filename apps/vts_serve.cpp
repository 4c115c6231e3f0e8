#include "apps/vts_serve.h"

#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "apps/cli.h"
#include "apps/vts_sim.h"
#include "pipeline/scenario.h"
#include "sensor/profile_exr.h"
#include "server/server.h"

namespace vts::apps {
namespace {

struct ServeOptions : BoxOptions {
  std::string listen, port, max_clients, cell, scene, scenario;
  bool allow_remote = false, realtime = false;
};

server::Server* g_server = nullptr;
void stop_on_signal(int) {
  if (g_server) g_server->stop();
}

int run_serve(const ServeOptions& o) {
  server::HostOptions host_options;
  if (!o.cell.empty() || !o.scene.empty()) {
    // Another cell: the box's own options do not apply.
    for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--offset", &o.offset},
                                 {"--rotation", &o.rotation}, {"--speed", &o.speed}})
      if (!v->empty()) cli::bad(opt, *v, "only for the box cell, not with --cell or --scene");
    if (o.cell == "box") {
      if (!o.scene.empty()) cli::bad("--cell", o.cell, "give --cell or --scene, not both");
    } else {
      Cell cell = cli::load_cell(o.cell, o.scene).cell;
      apply_sensor_options(o, cell.scanner);
      if (!o.rate.empty()) cell.scanner.rate_hz = cli::parse_positive("--rate", o.rate, "Hz");
      host_options.cell = std::move(cell);
    }
  }
  if (!o.scenario.empty()) {
    // A scenario of `vts sim`: its box cell, disturbances, robot, sensor and program.
    refuse_box_options(o, "--scenario");
    for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--cell", &o.cell}, {"--scene", &o.scene}})
      if (!v->empty()) cli::bad(opt, *v, "a scenario sets it in its file; not with --scenario");
    try {
      host_options.sim = find_scenario(o.scenario).spec;
    } catch (const ScenarioError& e) {
      throw cli::UsageError(e.what());
    }
    if (!o.source.empty()) host_options.sim.source = cli::parse_source("--source", o.source);
  } else {
    BoxOptions box = o;
    if (host_options.cell) box.sensor = box.material = box.rate = "";  // applied to the cell above
    host_options.sim = box_spec(box);  // the source and the seed, for any cell
  }
  host_options.realtime = o.realtime;
  host_options.robot = host_options.sim.robot;
  host_options.robot_seed = host_options.sim.robot_seed;
  cli::apply_thread_limit(o.threads);
  server::ServerOptions so;
  if (!o.listen.empty()) {
    const auto colon = o.listen.rfind(':');
    if (colon == std::string::npos) cli::bad("--listen", o.listen, "expected ADDRESS:PORT, e.g. 127.0.0.1:5170");
    so.address = o.listen.substr(0, colon);
    try {
      so.port = static_cast<int>(cli::parse_integer("--listen", o.listen.substr(colon + 1), 0, 65535));
    } catch (const cli::UsageError&) {
      cli::bad("--listen", o.listen, "expected ADDRESS:PORT with a port from 0 to 65535");
    }
  }
  if (!o.port.empty()) so.port = static_cast<int>(cli::parse_integer("--port", o.port, 0, 65535));
  if (!o.max_clients.empty()) so.max_clients = static_cast<int>(cli::parse_integer("--max-clients", o.max_clients, 1, 4096));
  so.allow_remote = o.allow_remote;

  server::CellHost host(host_options);
  server::Server srv(host, so);
  std::printf("listening %s:%d\n", srv.address().c_str(), srv.port());
  std::fflush(stdout);
  g_server = &srv;
  auto old_int = std::signal(SIGINT, stop_on_signal);
  auto old_term = std::signal(SIGTERM, stop_on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  srv.run();
  std::signal(SIGINT, old_int);
  std::signal(SIGTERM, old_term);
  g_server = nullptr;
  const server::ServerStats st = srv.stats();
  std::fprintf(stderr, "vts serve: stopped; %lld clients served, %lld requests, %lld pushes, %lld dropped (not reading), "
               "%lld refused, %lld lines too long\n",
               static_cast<long long>(st.accepted), static_cast<long long>(st.lines), static_cast<long long>(st.pushed),
               static_cast<long long>(st.dropped_slow), static_cast<long long>(st.refused),
               static_cast<long long>(st.too_long));
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_serve_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ServeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "serve",
      "The box cell of `vts sim` with its virtual robot and sensor on a TCP port, for a master program of your own:\n"
      "newline-delimited JSON, the sensor interface, a robot channel, lockstep or real time (docs/PROTOCOL.md).\n"
      "Prints 'listening ADDRESS:PORT' when ready; stops on SIGINT/SIGTERM.");
  cmd->option_defaults()->always_capture_default(false);
  add_box_options(cmd, *o);
  cmd->add_option("--listen", o->listen, "Address and port to listen on (default 127.0.0.1:5170; port 0: any free)")
      ->type_name("ADDR:PORT");
  cmd->add_option("--port", o->port, "Port on the --listen address (0: any free one)")->type_name("PORT");
  cmd->add_flag("--allow-remote", o->allow_remote,
                "Allow a --listen address other than loopback: anyone who reaches the port can drive the cell "
                "(docs/PROTOCOL.md, Security)");
  cmd->add_flag("--realtime", o->realtime,
                "Wall-clock time: profiles at the sensor's rate whether asked or not (default: lockstep, time "
                "advances on the master's `step`)");
  cmd->add_option("--cell", o->cell,
                  "Serve this built-in cell (`vts cells`) instead of the box: its workpieces and scanner, the sensor "
                  "mounted 50 mm ahead of the torch; each profile carries its joint's truth (default: box)")
      ->type_name("NAME");
  cmd->add_option("--scene", o->scene, "Serve the cell of this scene file (docs/SCENE_FORMAT.md)")->type_name("FILE");
  cmd->add_option("--scenario", o->scenario,
                  "Serve a scenario of `vts sim` (`vts sim --scenarios`, or a scenario file): its box cell with "
                  "the disturbances, its robot and sensor; sim.job carries its program (weave, move speed)")
      ->type_name("NAME|FILE.yaml");
  cmd->add_option("--max-clients", o->max_clients, "Most clients connected at once, 1..4096 (default 256)")
      ->type_name("N");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_serve(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts serve: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::invalid_argument& e) {
      std::cerr << "vts serve: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "vts serve: error: " << e.what() << "\n";
      exit_code = cli::kExitRuntime;
    }
  });
  return cmd;
}

}  // namespace vts::apps
