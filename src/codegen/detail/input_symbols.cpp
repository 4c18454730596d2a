#include <algorithm>

#include <symdyn/codegen/detail/input_symbols.hpp>
#include <symdyn/model/dynamics.hpp>

namespace symdyn::codegen::detail {

InputSymbols::InputSymbols(const model::Model& model) {
  for (const model::Coordinate& c : model.coordinates()) {
    symbols_[index(Input::q)].push_back(c.q);
    symbols_[index(Input::qd)].push_back(c.qd);
    symbols_[index(Input::qdd)].push_back(c.qdd);
  }
  symbols_[index(Input::t)] = {model.time()};
  symbols_[index(Input::tau)] = model::generalized_force_symbols(model);
  for (const model::Parameter& p : model.parameters())
    symbols_[index(Input::param)].push_back(p.symbol);
  symbols_[index(Input::F_applied)] = model::applied_force_symbols(model);
  symbols_[index(Input::M_applied)] = model::applied_moment_symbols(model);
  // One weight per loop equation, named after the implicit parameter of its row.
  for (std::size_t j = model.num_independent(); j < model.coordinates().size(); ++j) {
    symbols_[index(Input::mu)].push_back(
        symbolic::symbol("mu." + model.coordinates()[j].q.name(), symbolic::SymbolKind::Free));
  }
}

std::vector<model::Expr> InputSymbols::of(const std::vector<Input>& inputs) const {
  std::vector<model::Expr> out;
  for (Input in : inputs) out.insert(out.end(), (*this)[in].begin(), (*this)[in].end());
  return out;
}

std::vector<model::Expr> InputSymbols::all() const {
  return of({std::begin(kInputs), std::end(kInputs)});
}

std::vector<std::size_t> InputSymbols::indices(const std::vector<Input>& inputs) const {
  std::vector<std::size_t> out;
  std::size_t first = 0;
  for (Input in : kInputs) {
    const std::size_t n = size(in);
    if (std::find(inputs.begin(), inputs.end(), in) != inputs.end()) {
      for (std::size_t i = 0; i < n; ++i) out.push_back(first + i);
    }
    first += n;
  }
  return out;
}

std::string element(std::string_view name, std::size_t i) {
  std::string out(name);
  out += '[';
  out += std::to_string(i);
  out += ']';
  return out;
}

std::string input_element(Input input, std::size_t i) {
  return input == Input::t ? std::string("t") : element(input_name(input), i);
}

}  // namespace symdyn::codegen::detail
