#pragma once
// The previous newmark and generalized-alpha (newmark_baseline.cpp), as integrators of
// the runtime's interface, for newmark_bench.cpp to time beside today's in one run.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::bench {

std::unique_ptr<runtime::Integrator> make_newmark_baseline(runtime::IntegratorOptions options);
std::unique_ptr<runtime::Integrator> make_generalized_alpha_baseline(
    runtime::IntegratorOptions options);

}  // namespace symdyn::bench
