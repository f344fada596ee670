#pragma once
// A visitor of one lambda per alternative, for std::visit: a variant given a
// new alternative that no lambda takes does not compile.
namespace acpca {

template <typename... Lambdas>
struct Overloaded : Lambdas... {
  using Lambdas::operator()...;
};
template <typename... Lambdas>
Overloaded(Lambdas...) -> Overloaded<Lambdas...>;

}  // namespace acpca
