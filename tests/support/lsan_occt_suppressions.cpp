// LeakSanitizer suppressions for the sanitizer build (WIREFUR_SANITIZE=ON), compiled into the
// programs that load OpenCASCADE (the wirefur command, whose CAD worker reads files, the CAD tests
// and the CAD benchmark). OpenCASCADE's data exchange fills global registries lazily and never
// frees them (Interface_Static, IFSelect_Editor, TPrsStd_DriverTable, its memory manager's
// pools), and it is built without frame pointers, so the stacks stop inside it: leaks allocated
// inside its libraries are not reported. Allocations of our own code are checked as before.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libTKernel.so\n"
         "leak:libTKXSBase.so\n"
         "leak:libTKVCAF.so\n"
         "leak:libTKXCAF.so\n"
         "leak:libTKSTEP\n"
         "leak:libTKIGES.so\n"
         "leak:libTKXDE\n"
         "leak:libTKLCAF.so\n"
         "leak:libTKCAF.so\n"
         "leak:libTKBRep.so\n"
         "leak:libTKMesh.so\n";
}

// The suppressed leaks are not listed at exit either: a command's stderr is one line per problem
// (a render that reads a CAD file in-process, for silhouettes or fur, printed the list).
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
