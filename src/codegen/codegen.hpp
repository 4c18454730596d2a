#pragma once
// symdyn::codegen: from a model to the emitted C++ (generate.hpp), and the
// generators' command line (generator_cli.hpp, library symdyn::generator_main).

#include <symdyn/codegen/generate.hpp>
#include <symdyn/codegen/generator_cli.hpp>
