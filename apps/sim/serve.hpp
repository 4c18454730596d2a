#pragma once
// symdyn-sim --serve: one scenario run many times, each run with its own
// changes (overrides.hpp), on request: the engine of sweeps (docs/sweeps.md).
// The sweep driver (the Python package symdyn) keeps one such process per
// worker, so that a run costs no process start. One JSON object per line
// each way, on stdin and stdout:
//
//   -> {"load": {"scenario": {"builtin": "trike"} | {"text": "...", "origin": "trike.json",
//   "directory": "/abs"},
//                "origin": "tyres.json",
//                "targets": [{"path": "forces.front.stiffness", "at":
//                "/set/forces.front.stiffness"}, ...], "keep": {...}, "keep_at": "/keep", "check":
//                [2e5, 5]}}
//   <- {"loaded": {"columns": ["end(q0)", ...], "series": ["t", "q0", ...]}}   or   {"error":
//   "..."}
//   -> {"run": 7, "values": [2e5, 5]}
//   <- {"run": 7, "status": "ok", "error": "", "values": [...], "cpu": 0.0121, "wall": 0.0123,
//   "series": "t,q0\n..."}
//   -> {"runs": [{"run": 8, "values": [...]}, {"run": 9, "values": [...]}]}
//   <- one such line per run, written together when the last is made
//
// "load" reads the scenario, checks every target path against it and every
// kept quantity (errors name the sweep file's key: `origin`, then `at` or
// `keep_at` and below), and builds the run of the values `check` without
// running it. A run's values are given in the order of the targets; the row
// gives the kept columns in the order of "columns", NaN for a run that
// failed. status: ok; out_of_band (a check outside its band: error lists
// them); failed (error: what refused the run or stopped it). "series" (the
// scenario's CSV of the run) comes only when the sweep keeps it.
//
// Numbers print in the shortest form that reads back exactly, NaN and
// infinities as NaN, Infinity and -Infinity (as Python's json reads them): a
// sweep's table is the same bit for bit wherever its runs were made. cpu is
// the process's CPU time for the run (building it included), wall its
// elapsed time, both in seconds.

#include <istream>
#include <ostream>

namespace symdyn::sim {

// Serves requests until the end of `in`; returns the exit code (0).
int serve(std::istream& in, std::ostream& out);

}  // namespace symdyn::sim
