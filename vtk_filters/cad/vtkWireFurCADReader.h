/**
 * @class   vtkWireFurCADReader
 * @brief   reads STEP, IGES, BREP and FreeCAD files through OpenCASCADE, with exact surface data
 *
 * Reads a CAD file and tessellates it with OpenCASCADE's BRepMesh:
 * - .step / .stp and .iges / .igs through XCAF: part names, colours (of parts, instances and
 *   faces), assemblies and their locations, mirrored instances included;
 * - .brep (OpenCASCADE's own format);
 * - .FCStd (FreeCAD documents): the zip is read with libzip, Document.xml and GuiDocument.xml
 *   with pugixml; every visible object with a shape is read with its placement (App::Part
 *   containers included) and its shape colour or per-face colours (docs/cad.md).
 *
 * Output port 0 (faces): triangles, one set of vertices per face (not shared across faces), with
 * exact data from the face's surface at every vertex, not from averaged facets:
 * - point "Normals" (float, active normals): the oriented unit normal (REVERSED faces and mirroring
 *   locations handled: outward on closed solids), its limit at poles;
 * - point "TCoords" (double, active texture coordinates): the face's (u, v);
 * - point "Su" (double, active tangents) and "Sv": dS/du and dS/dv in world units;
 * - point "Colors" (unsigned char RGB, sRGB): the face's colour (grey where the file has none);
 * - cell "FaceId" (the face's index in the file, from 0) and "PartId" (index into "PartNames");
 * - field "PartNames" (vtkStringArray) and "LinearDeflection" (the applied linear deflection,
 *   world units: one double).
 * Triangles wind counter-clockwise about the normal.
 *
 * Output port 1 (edges): polylines, the model's edges (degenerate edges skipped) sampled to the
 * same deflection, taken from the face tessellation where the edge bounds a face so that wire and
 * surface meet without cracks; edges meeting at a vertex share its point. Optionally the faces'
 * u and v iso-parametric lines (NumberOfUIsoLines, NumberOfVIsoLines per face). Cell arrays
 * "Kind" (0 edge, 1 u iso line (u constant), 2 v iso line), "EdgeId" (edge or face index),
 * "PartId", "EdgeClass" (what lies on the edge's sides: 0 boundary (one face), 1 sharp, 2 smooth
 * (two faces whose normals differ by more, or at most, FeatureAngle degrees along it), 3 seam (the
 * same face on both sides), 4 free (no face), 5 non-manifold; -1 on iso lines) and "EdgeAngle"
 * (float: between two faces, the largest angle in degrees between their oriented normals at 9
 * points along the edge, from the exact surfaces; NaN where unknown or not between two faces).
 * Select with vtkThreshold on "EdgeClass" (seams, hidden by the wirefur command by default, are 3).
 *
 * Deflection: LinearDeflection is a fraction of the model's bounding-box diagonal when
 * RelativeDeflection is on (default 1e-3, so a 5 mm screw and a 50 m hull tessellate alike),
 * else world units; AngularDeflection in radians (default 0.35). GetAppliedLinearDeflection()
 * gives the value used, in world units.
 *
 * Bad input (missing, empty, truncated or corrupt file, another format, no faces and no edges, a
 * FreeCAD document without shapes) ends the update with both outputs empty, one error (VTK's
 * ErrorEvent) and the same line in GetErrorMessage(), naming the file and the entity; the
 * pipeline goes on (RequestData returns 1, as the module's filters do). Faces that fail to mesh are skipped and counted
 * (GetNumberOfSkippedFaces(), GetWarningMessage()); the rest is output. Some corrupt STEP and
 * IGES files crash OpenCASCADE 7.6 itself (fuzzing found null entities dereferenced in its STEP
 * and IGES translators), and some make it loop for ever: with ReadInWorker on, the file is read
 * and meshed in a process of its own (wirefur-cad-worker, beside this library), so that a crash,
 * a hang (WorkerTimeout) or the worker's memory cap becomes the one-line error above and the program
 * carries on. ParaView's proxy turns it on; the wirefur command has a worker of its own.
 *
 * OpenCASCADE is private to this module (hidden behind a PIMPL): this header needs only VTK.
 */
#ifndef vtkWireFurCADReader_h
#define vtkWireFurCADReader_h

#include "WireFurCADModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <string>

class WIREFURCAD_EXPORT vtkWireFurCADReader : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurCADReader* New();
  vtkTypeMacro(vtkWireFurCADReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read; the format is chosen by its extension (.step .stp .iges .igs .brep
  /// .fcstd, any case).
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /// True when the extension is one this reader reads.
  static bool CanReadFile(const char* fileName);

  ///@{
  /// Linear deflection: a fraction of the model's bounding-box diagonal when RelativeDeflection
  /// is on (default 1e-3), else world units. Clamped to [1e-9, 1e30].
  vtkSetClampMacro(LinearDeflection, double, 1e-9, 1e30);
  vtkGetMacro(LinearDeflection, double);
  vtkSetMacro(RelativeDeflection, bool);
  vtkGetMacro(RelativeDeflection, bool);
  vtkBooleanMacro(RelativeDeflection, bool);
  ///@}

  ///@{
  /// Angular deflection in radians (0.01 ... 1.5). Default 0.35 (about 20 degrees).
  vtkSetClampMacro(AngularDeflection, double, 0.01, 1.5);
  vtkGetMacro(AngularDeflection, double);
  ///@}

  ///@{
  /// Iso-parametric lines per face on the edges output (0 ... 1000 each). Default 0.
  vtkSetClampMacro(NumberOfUIsoLines, int, 0, 1000);
  vtkGetMacro(NumberOfUIsoLines, int);
  vtkSetClampMacro(NumberOfVIsoLines, int, 0, 1000);
  vtkGetMacro(NumberOfVIsoLines, int);
  ///@}

  ///@{
  /// Largest number of triangles (all faces together) before the update fails with a clear
  /// message instead of exhausting memory. Default 20,000,000.
  vtkSetClampMacro(MaximumTriangles, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaximumTriangles, vtkIdType);
  ///@}

  ///@{
  /// Degrees: two faces whose normals differ by more than this along their common edge meet at
  /// a sharp edge (EdgeClass 1), else a smooth one (2). Default 10 (render/edge_classes.h).
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  ///@}

  ///@{
  /// On: read the file and keep its exact faces for wirefur_cad_face_surfaces (every face, FaceId
  /// as a full update numbers them), with nothing meshed and both outputs empty: for a program
  /// that has the tessellation already (the wirefur command, from its worker process). Default off.
  vtkSetMacro(FacesOnly, bool);
  vtkGetMacro(FacesOnly, bool);
  vtkBooleanMacro(FacesOnly, bool);
  ///@}

  ///@{
  /// On: read and mesh the file in a child process (wirefur-cad-worker, found beside this
  /// library), which returns both outputs through a private temporary folder (under $TMPDIR); a
  /// crash, a hang past WorkerTimeout seconds (default 600; NaN is ignored) or the worker's
  /// memory cap ends the update with one line instead of taking the program down. The cap
  /// limits the data the worker maps (RLIMIT_DATA) to half the memory of the machine or of its
  /// cgroup, 1 to 16 GiB; a file that needs more fails in the worker ("out of memory in the CAD
  /// worker") where it might read in process (a failed allocation ends the worker: OpenCASCADE
  /// would skip the face). Otherwise the outputs are those read in process, bit for bit.
  /// Progress comes from the worker every 50 ms, and AbortExecute stops it. The
  /// worker dies with this process. The exact faces (wf_cad_plugin.h) are then read in this
  /// process only when asked for (vtkWireFurSilhouette), once the worker has shown that the file
  /// reads cleanly, and only if the file has not changed since (else none, with a warning).
  /// FacesOnly always reads in process. Default off.
  vtkSetMacro(ReadInWorker, bool);
  vtkGetMacro(ReadInWorker, bool);
  vtkBooleanMacro(ReadInWorker, bool);
  virtual void SetWorkerTimeout(double seconds);
  vtkGetMacro(WorkerTimeout, double);
  ///@}

  /// The worker's path (beside this library), or empty when it is not there.
  static std::string GetWorkerExecutable();

  ///@{
  /// Worker threads for meshing and evaluating faces (0: oneTBB's default). The output is the
  /// same, bit for bit, for any count.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /// What the last update found. Virtual so that a program that loads this module at run time
  /// (the wirefur command) can call them through the object.
  virtual int GetNumberOfParts() const;
  virtual std::string GetPartName(int part) const;
  /// Faces in the file, faces output, faces skipped (failed to mesh).
  virtual int GetNumberOfFaces() const;
  virtual int GetNumberOfMeshedFaces() const;
  virtual int GetNumberOfSkippedFaces() const;
  virtual int GetNumberOfEdges() const;
  /// Edges of one EdgeClass (0-5) in the output.
  virtual int GetNumberOfEdgesOfClass(int edgeClass) const;
  /// The linear deflection used, world units.
  virtual double GetAppliedLinearDeflection() const;
  /// Bounding-box diagonal of the model, world units.
  virtual double GetModelSize() const;
  /// Seconds spent reading the file and meshing the faces.
  virtual double GetReadSeconds() const;
  virtual double GetMeshSeconds() const;
  /// Empty after a good update; otherwise one line: "FILE: entity: problem".
  virtual std::string GetErrorMessage() const;
  /// Empty, or one line about what was skipped.
  virtual std::string GetWarningMessage() const;
  ///@}

protected:
  vtkWireFurCADReader();
  ~vtkWireFurCADReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestDataInWorker(const std::string& path, vtkPolyData* faces, vtkPolyData* edges);

  char* FileName = nullptr;
  double LinearDeflection = 1e-3;
  bool RelativeDeflection = true;
  double AngularDeflection = 0.35;
  int NumberOfUIsoLines = 0;
  int NumberOfVIsoLines = 0;
  vtkIdType MaximumTriangles = 20000000;
  int NumberOfThreads = 0;
  double FeatureAngle = 10.0;
  bool FacesOnly = false;
  bool ReadInWorker = false;
  double WorkerTimeout = 600.0;

public:
#ifndef __VTK_WRAP__
  /// The module's own C entry points (wf_cad_plugin.h) read the faces kept from the last update.
  class vtkInternals;
  vtkInternals* GetInternals() { return this->Internals; }
#endif

private:
  vtkWireFurCADReader(const vtkWireFurCADReader&) = delete;
  void operator=(const vtkWireFurCADReader&) = delete;

  vtkInternals* Internals;
};

#endif
