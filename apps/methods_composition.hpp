// Methods: symmetric compositions, commutator-free and Crouch-Grossman methods (see registry.hpp).
//   cf4, cg3                 integrators/commutator_free.hpp
//   lgvi_<coefficients>      compositions of the LGVI (integrators/composition.hpp)
//   split_dmv_<coefficients> compositions of kick + DMV (integrators/composition.hpp, splitting.hpp)
#pragma once

#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>

namespace lgi::app {
using CompositionMethods =
    MethodList<Cf4, Cg3, LgviYoshida4, LgviSuzuki4, LgviYoshida6, LgviKahanLi6, LgviYoshida8, LgviKahanLi8,
               LgviSofroniouSpaletta10, SplitDmvYoshida4, SplitDmvSuzuki4, SplitDmvKahanLi6, SplitDmvKahanLi8,
               SplitDmvSofroniouSpaletta10>;
}  // namespace lgi::app
