// The generator's main: linked with a model file, it is that model's generator
// (command line: generator_cli.hpp).
#include <symdyn/codegen/generator_cli.hpp>

int main(int argc, char** argv) {
  return symdyn::codegen::run_generator(argc, argv);
}
