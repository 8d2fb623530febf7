#include "nsmodal/witness.h"

namespace nsmodal {

Witness ContactWitness(int contact, bool held) {
  Witness w;
  w.kind = held ? WitnessKind::kContactForce : WitnessKind::kGap;
  w.contact = contact;
  w.name = "contact " + std::to_string(contact + 1) + (held ? " force" : " gap");
  return w;
}

}  // namespace nsmodal
