// The functions of the module `fss`, one file a domain: each adds its
// functions (and classes) to the module.
#pragma once
#include <pybind11/pybind11.h>

namespace fss::python {

void define_simulate(pybind11::module_& m);   // simulate_bindings.cpp
void define_codes(pybind11::module_& m);      // code_bindings.cpp
void define_images(pybind11::module_& m);     // image_bindings.cpp
void define_campaigns(pybind11::module_& m);  // campaign_bindings.cpp

}  // namespace fss::python
