// The Gmsh (SDK 4.8) session of the curve bridge (GmshCurves) and the body bridge (GmshMesh),
// opened inside the sandboxed child process (meshes/GmshSandbox) only: initialized quietly
// (General.Terminal = 0) and finalized on every exit path by the guard. A session the child
// inherited from its parent (a copy of the parent's memory) is finalized first; the parent's
// own session is not touched.
#pragma once

namespace flexsens {

/// Gmsh 4.8 has no gmsh::isInitialized(): an option read into a NaN probes the state.
bool gmshInitialized();

class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

}  // namespace flexsens
