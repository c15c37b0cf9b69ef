#include "dynamap/objects/object_table.h"

namespace dynamap {

const char* toString(ObjectState s) {
  switch (s) {
    case ObjectState::Present:
      return "present";
    case ObjectState::Absent:
      return "absent";
    case ObjectState::Withdrawn:
      return "withdrawn";
    case ObjectState::Relabeled:
      return "relabeled";
    case ObjectState::Retracted:
      return "retracted";
  }
  return "?";
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
    case ObjectEvent::Withdrawn:
      return "withdrawn";
    case ObjectEvent::Relabeled:
      return "relabeled";
    case ObjectEvent::Retracted:
      return "retracted";
  }
  return "?";
}

}  // namespace dynamap
