#include "dynamap/objects/object_table.h"

namespace dynamap {

const char* toString(ObjectState s) {
  return s == ObjectState::Present ? "present" : "absent";
}

const char* toString(ObjectEvent e) {
  switch (e) {
    case ObjectEvent::New:
      return "new";
    case ObjectEvent::Moved:
      return "moved";
    case ObjectEvent::Disappeared:
      return "disappeared";
    case ObjectEvent::Reappeared:
      return "reappeared";
  }
  return "?";
}

}  // namespace dynamap
