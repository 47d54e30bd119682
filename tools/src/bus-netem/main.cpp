// bus-netem --queue N --stats FILE [--loss-pct L] [--delay-ms D]
//           [--jitter-ms J] [--seed K] [--exempt CH1,CH2] [--in-order]
// netem for the LCM bus where the kernel has no sch_netem: takes the
// packets a netfilter rule queues to NFQUEUE N (tools/netem-run queues the
// bus group's UDP port on INPUT, inside a private network namespace),
// drops L % of them and lets the others through after D +- J ms
// (lib/netem/impairment.h). Rewrites FILE with the per-channel counts every
// second and at SIGTERM / SIGINT, then exits 0. Exit 2: bad arguments or
// no queue (needs CAP_NET_ADMIN).
#include <arpa/inet.h>
#include <libnetfilter_queue/libnetfilter_queue.h>
#include <linux/netfilter.h>
#include <poll.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <queue>
#include <sstream>

#include "netem/impairment.h"

namespace {

volatile sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

using Clock = std::chrono::steady_clock;
const Clock::time_point g_t0 = Clock::now();
double now_s() { return std::chrono::duration<double>(Clock::now() - g_t0).count(); }

// Ties (packets held to the same time, as --in-order makes them) go in
// arrival order.
struct Held {
  double release_s;
  uint64_t arrival;
  uint32_t id;
  bool operator>(const Held& o) const {
    return release_s != o.release_s ? release_s > o.release_s : arrival > o.arrival;
  }
};

struct State {
  evade::netem::Impairment* imp = nullptr;
  std::priority_queue<Held, std::vector<Held>, std::greater<Held>> held;
  nfq_q_handle* qh = nullptr;
  uint64_t arrivals = 0;
};

int on_packet(nfq_q_handle* qh, nfgenmsg*, nfq_data* nfa, void* data) {
  auto* st = static_cast<State*>(data);
  const nfqnl_msg_packet_hdr* ph = nfq_get_msg_packet_hdr(nfa);
  if (!ph) return 0;
  const uint32_t id = ntohl(ph->packet_id);
  unsigned char* payload = nullptr;
  const int len = nfq_get_payload(nfa, &payload);
  const double t = now_s();
  const auto v = st->imp->on_packet(payload, len > 0 ? static_cast<size_t>(len) : 0, t);
  if (v.drop) return nfq_set_verdict(qh, id, NF_DROP, 0, nullptr);
  if (v.release_s <= t) return nfq_set_verdict(qh, id, NF_ACCEPT, 0, nullptr);
  st->held.push({v.release_s, st->arrivals++, id});
  return 0;
}

void write_stats(const std::string& path, const evade::netem::Impairment& imp) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << imp.stats_json() << "\n";
  }
  std::rename(tmp.c_str(), path.c_str());
}

void release_due(State& st) {
  const double t = now_s();
  while (!st.held.empty() && st.held.top().release_s <= t) {
    nfq_set_verdict(st.qh, st.held.top().id, NF_ACCEPT, 0, nullptr);
    st.held.pop();
  }
}

// Receives queued packets and lets the held ones go when due, until a signal.
void serve(nfq_handle* h, State& st, const std::string& stats_path) {
  const int fd = nfq_fd(h);
  alignas(8) char buf[0x20000];
  double next_stats = 0;
  while (!g_stop) {
    release_due(st);
    int timeout_ms = 100;
    if (!st.held.empty()) timeout_ms = std::max(0, static_cast<int>(1e3 * (st.held.top().release_s - now_s())));
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, std::min(timeout_ms, 100)) > 0) {
      const ssize_t n = recv(fd, buf, sizeof buf, MSG_DONTWAIT);
      if (n > 0)
        nfq_handle_packet(h, buf, static_cast<int>(n));
      else if (n < 0 && errno == ENOBUFS)
        std::fprintf(stderr, "bus-netem: queue overrun (ENOBUFS)\n");
    }
    if (now_s() >= next_stats) write_stats(stats_path, *st.imp), next_stats = now_s() + 1.0;
  }
  while (!st.held.empty()) nfq_set_verdict(st.qh, st.held.top().id, NF_ACCEPT, 0, nullptr), st.held.pop();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"netem for the LCM bus through a netfilter queue"};
  uint16_t queue = 0;
  std::string stats_path, exempt = "SIM_TRUTH";
  double loss_pct = 5, delay_ms = 20, jitter_ms = 20;
  uint64_t seed = 1;
  app.add_option("--queue", queue, "NFQUEUE number")->required();
  app.add_option("--stats", stats_path, "per-channel counts (JSON), rewritten every second")->required();
  app.add_option("--loss-pct", loss_pct, "packets dropped, % (default 5)")->check(CLI::Range(0.0, 100.0));
  app.add_option("--delay-ms", delay_ms, "mean delay (default 20)")->check(CLI::NonNegativeNumber);
  app.add_option("--jitter-ms", jitter_ms, "uniform +- around the mean (default 20)")->check(CLI::NonNegativeNumber);
  app.add_option("--seed", seed, "random seed (default 1)");
  bool in_order = false;
  app.add_flag("--in-order", in_order, "no packet overtakes another (netem's jitter reorders them)");
  app.add_option("--exempt", exempt, "channels let through untouched (default SIM_TRUTH; '' for none)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  evade::netem::ImpairmentParams p{loss_pct / 100.0, delay_ms / 1e3, jitter_ms / 1e3, seed, {}};
  p.reorder = !in_order;
  std::stringstream ss(exempt);
  for (std::string ch; std::getline(ss, ch, ',');)
    if (!ch.empty()) p.exempt.insert(ch);
  evade::netem::Impairment imp(p);
  State st;
  st.imp = &imp;
  nfq_handle* h = nfq_open();
  if (!h || (st.qh = nfq_create_queue(h, queue, &on_packet, &st)) == nullptr ||
      nfq_set_mode(st.qh, NFQNL_COPY_PACKET, 0xffff) < 0) {
    std::fprintf(stderr, "bus-netem: cannot bind NFQUEUE %u (%s; needs CAP_NET_ADMIN)\n", queue, std::strerror(errno));
    return 2;
  }
  nfq_set_queue_maxlen(st.qh, 16384);
  nfnl_rcvbufsiz(nfq_nfnlh(h), 32 << 20);
  signal(SIGTERM, on_signal);
  signal(SIGINT, on_signal);
  serve(h, st, stats_path);
  write_stats(stats_path, imp);
  nfq_destroy_queue(st.qh);
  nfq_close(h);
  return 0;
}
