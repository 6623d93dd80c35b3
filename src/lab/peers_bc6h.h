// Published speed and error of public BC6H encoders on the shared test images, as measured in
// tests/data/bc6h/PEERS.md ("Measured 2026-12-01": one thread's CPU time, encode only, median
// of 3; log-RMSE over log2(1 + x)). Reference points of `ahdpack bench bc6h --plot`.
#pragma once
#include <string>
#include <vector>

namespace ahd::cli {

struct PeerFigure {
  std::string encoder;  // encoder and setting, as PEERS.md names it
  std::string image;    // file name in tests/data/bc6h
  double mpix_per_s;    // MPix/s of one thread's CPU time
  double log_rmse;
};

// The date of the measurement the table holds.
inline constexpr const char* kPeersBc6hDate = "2026-12-01";

// Every published figure (images without a figure in PEERS.md are absent).
const std::vector<PeerFigure>& peers_bc6h();

}  // namespace ahd::cli
