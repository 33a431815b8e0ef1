// `flexsens static` from a test: run the scene through the command line and read the .vtu of
// its last frame (the last load step), as a user's ParaView would.
#pragma once

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace flexsens::test {

/// Runs `flexsens static yaml --out out`; null when it fails or writes no frame.
inline vtkSmartPointer<vtkUnstructuredGrid> staticLastFrame(const std::filesystem::path& yaml,
                                                           const std::filesystem::path& out) {
  const std::string cmd = std::string(FLEXSENS_EXE) + " static " + yaml.string() + " --out " + out.string() +
                          " > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) return nullptr;
  std::filesystem::path vtu;  // frame_NNNNN.vtu: the largest name is the last frame
  for (const auto& e : std::filesystem::directory_iterator(out))
    if (e.path().extension() == ".vtu" && (vtu.empty() || e.path() > vtu)) vtu = e.path();
  if (vtu.empty()) return nullptr;
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(vtu.c_str());
  reader->Update();
  return reader->GetOutput();
}

}  // namespace flexsens::test
