// The default procedural head, built once per test binary (it takes a few seconds).
#pragma once
#include "synth/subject.h"

namespace lorgnette::synth::test {

inline const Subject& default_head() {
  static const Subject s = procedural_subject(random_head_params(0));
  return s;
}

}  // namespace lorgnette::synth::test
