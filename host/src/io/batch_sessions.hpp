#pragma once
// The batch-recognition files of `sva recognize` (docs/batch-format.md): the
// sessions file (JSON Lines, one session of readings per line) and the results
// file (one estimate per session, in input order). Reading checks every field
// before any recognition runs; an error names FILE:LINE, the field and the fault.
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/recognizer.hpp>

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace sva::io {

struct BatchSession {
  std::string id;                 // from the file, else the session's number
  std::vector<Reading> readings;  // at least one
  nlohmann::json truth;           // copied to the result when present (null otherwise)
};

// Reads a sessions file whose pressure images have `elements` values (the map's sensor).
std::vector<BatchSession> read_batch_sessions(const std::string& file, int elements);

// Writes sessions in the same format (position, normal, x axis and pressure of every reading).
void write_batch_sessions(const std::string& file, std::span<const BatchSession> sessions);

// A pose as the results file writes it: R row by row, T and the Rodrigues vector.
nlohmann::json pose_json(const RigidPose& pose);

// Writes one result line per session (sessions[i] with estimates[i]); `objects`
// names the map's objects in order.
void write_batch_results(const std::string& file, std::span<const BatchSession> sessions,
                         std::span<const Estimate> estimates, std::span<const std::string> objects);

}  // namespace sva::io
