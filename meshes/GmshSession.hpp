// One Gmsh (SDK 4.8) session at a time, shared by the curve bridge (GmshCurves) and the
// body bridge (GmshMesh): Gmsh has global state, so calls hold gmshMutex(); a session is
// initialized quietly (General.Terminal = 0) and finalized on every exit path by the guard.
#pragma once

#include <mutex>

namespace flexsens {

/// Gmsh 4.8 has no gmsh::isInitialized(): an option read into a NaN probes the state.
bool gmshInitialized();

std::mutex& gmshMutex();

class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

}  // namespace flexsens
