// The PETSc/MPI backend of the static solve (petsc_solver.hpp).
#include "isospring/analysis/petsc_solver.hpp"

#include "isospring/nurbs/error.hpp"

#if ISOSPRING_HAVE_PETSC
#include <petscksp.h>

#include <Eigen/Core>
#include <chrono>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "assembly_structure.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "static_result.hpp"
#endif

namespace isospring::analysis {

#if !ISOSPRING_HAVE_PETSC

bool petsc_available() {
  return false;
}

PetscSession::PetscSession() {
  throw nurbs::InputError(
      "this isospring was built without PETSc, so the distributed backend is missing: install "
      "the Debian packages libpetsc-real-dev and openmpi-bin (bash scripts/setup.sh) and "
      "rebuild (cmake -DISOSPRING_WITH_PETSC=ON), or use the serial solver");
}

PetscSession::~PetscSession() = default;

void PetscSession::on_root(const std::function<void()>& step) const {
  step();
}

StaticResult solve_static_petsc(const Problem&, const PetscSolverOptions&) {
  throw nurbs::InputError("this isospring was built without PETSc (see PetscSession)");
}

StaticResult solve_static_amg(const Problem&, const PetscSolverOptions&) {
  throw nurbs::InputError(
      "this isospring was built without PETSc, which the algebraic multigrid solver uses: "
      "install libpetsc-real-dev (bash scripts/setup.sh) and rebuild, or use --solver cg or "
      "cholesky");
}

#else

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// PETSc's first message of the error being returned ("Unable to find requested PC type x").
thread_local std::string petsc_error_message;

// Replaces PETSc's default traceback handler, which on a rank other than 0 sleeps 10 s and calls
// exit(0) for an error in a collective call: rank 1 then vanished without MPI_Finalize and
// mpirun killed rank 0 before it could say why. This one keeps the message and returns the
// error, which check() turns into an exception on every rank.
PetscErrorCode record_error(MPI_Comm, int, const char*, const char*, PetscErrorCode code,
                            PetscErrorType type, const char* message, void*) {
  if (type == PETSC_ERROR_INITIAL) petsc_error_message = message ? message : "";
  return code;
}

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  std::string text = petsc_error_message;
  if (text.empty()) {
    const char* generic = nullptr;
    PetscErrorMessage(code, &generic, nullptr);
    text = generic ? generic : "error " + std::to_string(code);
  }
  petsc_error_message.clear();
  throw std::runtime_error(std::string("PETSc: ") + what + " failed: " + text);
}

// Owns one PETSc object and destroys it on scope exit (exceptions included).
template <class T, PetscErrorCode (*Destroy)(T*)>
struct Owned {
  T handle = nullptr;
  Owned() = default;
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (handle) Destroy(&handle);
  }
  T* operator&() { return &handle; }
  operator T() const { return handle; }
};
using OwnedMat = Owned<Mat, MatDestroy>;
using OwnedVec = Owned<Vec, VecDestroy>;
using OwnedIS = Owned<IS, ISDestroy>;
using OwnedKSP = Owned<KSP, KSPDestroy>;
using OwnedScatter = Owned<VecScatter, VecScatterDestroy>;
using OwnedNullSpace = Owned<MatNullSpace, MatNullSpaceDestroy>;

// An error found on some ranks only: the message and whether it is bad input (exit status 1) or
// a failed computation (std::runtime_error, exit status 3).
struct RankError {
  std::string message;
  bool input = true;
};

// Every rank calls this at the same point. When any rank has an error, every rank throws the
// error of the lowest such rank: a rank throwing alone would leave the others waiting forever
// in their next collective call (an element with a bad Jacobian is found only by its owner).
void agree_on_error(MPI_Comm comm, const RankError& error) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int mine = error.message.empty() ? INT_MAX : rank;
  int first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == INT_MAX) return;
  int header[2] = {static_cast<int>(error.message.size()), error.input ? 1 : 0};
  MPI_Bcast(header, 2, MPI_INT, first, comm);
  std::string message =
      rank == first ? error.message : std::string(static_cast<size_t>(header[0]), ' ');
  MPI_Bcast(message.data(), header[0], MPI_CHAR, first, comm);
  if (header[1]) throw nurbs::InputError(message);
  throw std::runtime_error(message);
}

// Reads the owned entries of a PETSc vector (local index i = global row - first row).
class VecRead {
 public:
  explicit VecRead(Vec v) : v_(v) { check(VecGetArrayRead(v, &data_), "VecGetArrayRead"); }
  ~VecRead() { VecRestoreArrayRead(v_, &data_); }
  VecRead(const VecRead&) = delete;
  VecRead& operator=(const VecRead&) = delete;
  double operator[](PetscInt i) const { return data_[i]; }

 private:
  Vec v_;
  const PetscScalar* data_ = nullptr;
};

class VecWrite {
 public:
  explicit VecWrite(Vec v) : v_(v) { check(VecGetArray(v, &data_), "VecGetArray"); }
  ~VecWrite() { VecRestoreArray(v_, &data_); }
  VecWrite(const VecWrite&) = delete;
  VecWrite& operator=(const VecWrite&) = delete;
  double& operator[](PetscInt i) { return data_[i]; }

 private:
  Vec v_;
  PetscScalar* data_ = nullptr;
};

// The distribution: contiguous element ranges per rank, each node owned by the lowest rank of
// the elements around it, and the PETSc numbering in which every rank's nodes are contiguous
// (PETSc's requirement for row ownership): rank 0's nodes, then rank 1's, each in DofMap order.
struct Distribution {
  std::vector<int> element_start;  // rank r assembles elements [element_start[r], [r + 1])
  std::vector<int> owner;          // DofMap node -> rank
  std::vector<int> petsc_node;     // DofMap node -> PETSc node (block row)
  std::vector<int> node_start;     // rank r owns PETSc nodes [node_start[r], [r + 1])
};

Distribution distribute(const detail::AssemblyStructure& structure, int num_nodes, int size) {
  Distribution d;
  const long long num_elements = static_cast<long long>(structure.elements.size());
  d.element_start.resize(static_cast<size_t>(size) + 1);
  for (int r = 0; r <= size; ++r)
    d.element_start[static_cast<size_t>(r)] = static_cast<int>(num_elements * r / size);
  d.owner.assign(static_cast<size_t>(num_nodes), -1);
  for (int r = 0; r < size; ++r)
    for (int e = d.element_start[static_cast<size_t>(r)];
         e < d.element_start[static_cast<size_t>(r) + 1]; ++e)
      for (int k = structure.node_offset[static_cast<size_t>(e)];
           k < structure.node_offset[static_cast<size_t>(e) + 1]; ++k) {
        int& o = d.owner[static_cast<size_t>(structure.nodes[static_cast<size_t>(k)])];
        if (o < 0) o = r;
      }
  // Every control point supports some element of its patch; rank 0 keeps any other (none).
  for (int& o : d.owner)
    if (o < 0) o = 0;
  d.node_start.assign(static_cast<size_t>(size) + 1, 0);
  for (int o : d.owner) ++d.node_start[static_cast<size_t>(o) + 1];
  for (int r = 0; r < size; ++r)
    d.node_start[static_cast<size_t>(r) + 1] += d.node_start[static_cast<size_t>(r)];
  std::vector<int> next(d.node_start.begin(), d.node_start.end() - 1);
  d.petsc_node.resize(static_cast<size_t>(num_nodes));
  for (int n = 0; n < num_nodes; ++n)
    d.petsc_node[static_cast<size_t>(n)] =
        next[static_cast<size_t>(d.owner[static_cast<size_t>(n)])]++;
  return d;
}

// Block nonzeros per owned block row, in the diagonal block (columns owned by this rank) and
// off it: the nodes sharing an element with the row's node, over every element around it (those
// of other ranks add into this rank's rows too).
void count_nonzeros(const detail::AssemblyStructure& structure, const Distribution& d, int rank,
                    std::vector<PetscInt>& diagonal, std::vector<PetscInt>& off_diagonal) {
  const int first = d.node_start[static_cast<size_t>(rank)];
  const int owned = d.node_start[static_cast<size_t>(rank) + 1] - first;
  const int num_elements = static_cast<int>(structure.elements.size());
  std::vector<int> touch_offset(static_cast<size_t>(owned) + 1, 0);
  auto local_node = [&](int node) {
    return d.owner[static_cast<size_t>(node)] == rank
               ? d.petsc_node[static_cast<size_t>(node)] - first
               : -1;
  };
  for (int e = 0; e < num_elements; ++e)
    for (int k = structure.node_offset[static_cast<size_t>(e)];
         k < structure.node_offset[static_cast<size_t>(e) + 1]; ++k) {
      const int i = local_node(structure.nodes[static_cast<size_t>(k)]);
      if (i >= 0) ++touch_offset[static_cast<size_t>(i) + 1];
    }
  for (int i = 0; i < owned; ++i)
    touch_offset[static_cast<size_t>(i) + 1] += touch_offset[static_cast<size_t>(i)];
  std::vector<int> touch(static_cast<size_t>(touch_offset.back()));
  {
    std::vector<int> fill(touch_offset.begin(), touch_offset.end() - 1);
    for (int e = 0; e < num_elements; ++e)
      for (int k = structure.node_offset[static_cast<size_t>(e)];
           k < structure.node_offset[static_cast<size_t>(e) + 1]; ++k) {
        const int i = local_node(structure.nodes[static_cast<size_t>(k)]);
        if (i >= 0) touch[static_cast<size_t>(fill[static_cast<size_t>(i)]++)] = e;
      }
  }
  diagonal.assign(static_cast<size_t>(owned), 0);
  off_diagonal.assign(static_cast<size_t>(owned), 0);
  std::vector<int> mark(d.owner.size(), -1);
  for (int i = 0; i < owned; ++i)
    for (int t = touch_offset[static_cast<size_t>(i)]; t < touch_offset[static_cast<size_t>(i) + 1];
         ++t) {
      const int e = touch[static_cast<size_t>(t)];
      for (int k = structure.node_offset[static_cast<size_t>(e)];
           k < structure.node_offset[static_cast<size_t>(e) + 1]; ++k) {
        const int a = structure.nodes[static_cast<size_t>(k)];
        if (mark[static_cast<size_t>(a)] == i) continue;
        mark[static_cast<size_t>(a)] = i;
        ++(d.owner[static_cast<size_t>(a)] == rank ? diagonal
                                                   : off_diagonal)[static_cast<size_t>(i)];
      }
    }
}

}  // namespace

bool petsc_available() {
  return true;
}

PetscSession::PetscSession() {
  PetscBool initialized = PETSC_FALSE;
  check(PetscInitialized(&initialized), "PetscInitialized");
  if (!initialized) {
    check(PetscInitializeNoArguments(), "PetscInitialize");
    finalize_ = true;
    check(PetscPushErrorHandler(record_error, nullptr), "PetscPushErrorHandler");
  }
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
  MPI_Comm_size(PETSC_COMM_WORLD, &size_);
}

PetscSession::~PetscSession() {
  if (!finalize_) return;
  PetscPopErrorHandler();
  PetscFinalize();
}

void PetscSession::on_root(const std::function<void()>& step) const {
  RankError error;
  if (rank_ == 0) try {
      step();
    } catch (const nurbs::InputError& e) {
      error = {e.what(), true};
    } catch (const std::exception& e) {
      error = {e.what(), false};
    }
  agree_on_error(PETSC_COMM_WORLD, error);
}

namespace {
// The solve of solve_static_petsc on the ranks of `comm`: PETSC_COMM_WORLD for the distributed
// backend, PETSC_COMM_SELF for the serial AMG solver (solve_static_amg).
StaticResult solve_on(MPI_Comm comm, const Problem& problem, const PetscSolverOptions& options) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);

  // Every rank validates and numbers the same problem, so input errors are found by all alike.
  const ThreadScope threads(options.threads);
  const SupportedProblem supported = number_and_support(problem);
  const DofMap& dofs = supported.dofs;
  const Constraints& constraints = supported.constraints;

  StaticResult result;
  result.dofs = dofs.num_dofs();
  result.ranks = size;
  auto start = std::chrono::steady_clock::now();
  const int dim = dofs.dofs_per_node();
  const detail::AssemblyStructure structure(problem, dofs, /*with_pattern=*/false);
  const Distribution d = distribute(structure, dofs.num_nodes(), size);
  const int first_node = d.node_start[static_cast<size_t>(rank)];
  const int owned_nodes = d.node_start[static_cast<size_t>(rank) + 1] - first_node;
  const PetscInt local_rows = static_cast<PetscInt>(owned_nodes) * dim;
  const PetscInt first_row = static_cast<PetscInt>(first_node) * dim;
  auto petsc_row = [&](int dof) {
    return static_cast<PetscInt>(d.petsc_node[static_cast<size_t>(dof / dim)]) * dim + dof % dim;
  };

  OwnedMat K;
  RankError error;
  if (size == 1) {
    // One process (the serial AMG solver): the serial assembler on all threads, copied into
    // PETSc's AIJ as full rows; the PETSc numbering is the DofMap's (one rank owns every node,
    // in order). Element by element through MatSetValuesBlocked took twice as long on one thread.
    const Eigen::SparseMatrix<double> upper = assemble_stiffness(problem, dofs);
    Eigen::SparseMatrix<double, Eigen::RowMajor> full = upper.selfadjointView<Eigen::Upper>();
    full.makeCompressed();
    const std::vector<PetscInt> rows(full.outerIndexPtr(), full.outerIndexPtr() + full.rows() + 1);
    const std::vector<PetscInt> columns(full.innerIndexPtr(),
                                        full.innerIndexPtr() + full.nonZeros());
    check(MatCreate(comm, &K), "MatCreate");
    check(MatSetSizes(K, local_rows, local_rows, PETSC_DETERMINE, PETSC_DETERMINE), "MatSetSizes");
    check(MatSetBlockSize(K, dim), "MatSetBlockSize");
    check(MatSetType(K, MATSEQAIJ), "MatSetType");
    check(MatSetFromOptions(K), "MatSetFromOptions");
    check(MatSeqAIJSetPreallocationCSR(K, rows.data(), columns.data(), full.valuePtr()),
          "MatSeqAIJSetPreallocationCSR");
  } else {
    std::vector<PetscInt> diagonal, off_diagonal;
    count_nonzeros(structure, d, rank, diagonal, off_diagonal);
    check(MatCreate(comm, &K), "MatCreate");
    check(MatSetSizes(K, local_rows, local_rows, PETSC_DETERMINE, PETSC_DETERMINE), "MatSetSizes");
    check(MatSetBlockSize(K, dim), "MatSetBlockSize");
    check(MatSetType(K, MATAIJ), "MatSetType");
    check(MatSetFromOptions(K), "MatSetFromOptions");
    check(MatXAIJSetPreallocation(K, dim, diagonal.data(), off_diagonal.data(), nullptr, nullptr),
          "MatXAIJSetPreallocation");
    // This rank's elements with the serial kernel; entries of rows owned by other ranks are
    // stashed by PETSc and sent in MatAssemblyBegin/End.
    const detail::ElementStiffness kernel(problem, structure);
    detail::QuadraturePoint point;
    Eigen::MatrixXd local;
    std::vector<PetscInt> blocks;
    for (int e = d.element_start[static_cast<size_t>(rank)];
         e < d.element_start[static_cast<size_t>(rank) + 1]; ++e) {
      try {
        kernel(e, point, local);
      } catch (const std::exception& ex) {
        error.message = ex.what();
        break;
      }
      blocks.clear();
      for (int k = structure.node_offset[static_cast<size_t>(e)];
           k < structure.node_offset[static_cast<size_t>(e) + 1]; ++k)
        blocks.push_back(
            d.petsc_node[static_cast<size_t>(structure.nodes[static_cast<size_t>(k)])]);
      const PetscInt n = static_cast<PetscInt>(blocks.size());
      // `local` is symmetric, so its column-major storage is the row-major array PETSc reads.
      check(MatSetValuesBlocked(K, n, blocks.data(), n, blocks.data(), local.data(), ADD_VALUES),
            "MatSetValuesBlocked");
    }
  }
  check(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  agree_on_error(comm, error);
  result.assembly_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  // Rigid-body near-null space from the control points: control values a + w x X_a give exactly
  // the rigid motion a + w x x (the NURBS basis reproduces the geometry), so these are the exact
  // null space of the unsupported K, which smoothed aggregation needs for elasticity.
  OwnedVec coordinates;
  check(VecCreateMPI(comm, local_rows, PETSC_DETERMINE, &coordinates), "VecCreateMPI");
  check(VecSetBlockSize(coordinates, dim), "VecSetBlockSize");
  {
    VecWrite x(coordinates);
    const auto& positions = dofs.node_positions();
    for (int node = 0; node < dofs.num_nodes(); ++node)
      if (d.owner[static_cast<size_t>(node)] == rank)
        for (int c = 0; c < dim; ++c)
          x[(d.petsc_node[static_cast<size_t>(node)] - first_node) * dim + c] =
              positions[static_cast<size_t>(node)][c];
  }
  OwnedNullSpace rigid;
  check(MatNullSpaceCreateRigidBody(coordinates, &rigid), "MatNullSpaceCreateRigidBody");
  check(MatSetNearNullSpace(K, rigid), "MatSetNearNullSpace");

  // Supports: the prescribed DOFs of the serial solver. The rows this rank owns, increasing.
  std::vector<PetscInt> fixed_rows;
  std::vector<double> fixed_values;
  for (size_t k = 0; k < constraints.dofs.size(); ++k) {
    const int dof = constraints.dofs[k];
    if (d.owner[static_cast<size_t>(dof / dim)] != rank) continue;
    fixed_rows.push_back(petsc_row(dof));
    fixed_values.push_back(constraints.values[k]);
  }
  OwnedVec prescribed, coupling;
  check(MatCreateVecs(K, &prescribed, &coupling), "MatCreateVecs");
  check(VecSet(prescribed, 0.0), "VecSet");
  {
    VecWrite u(prescribed);
    for (size_t k = 0; k < fixed_rows.size(); ++k) u[fixed_rows[k] - first_row] = fixed_values[k];
  }
  // coupling = K u_c: its free rows are K_fc u_c (moved to the right-hand side), its supported
  // rows K_cc u_c. The supported rows of K are kept (K_c, few rows) for the reactions K u - f.
  check(MatMult(K, prescribed, coupling), "MatMult");
  OwnedMat supported_rows;
  {
    OwnedIS rows, columns;
    check(ISCreateGeneral(comm, static_cast<PetscInt>(fixed_rows.size()), fixed_rows.data(),
                          PETSC_COPY_VALUES, &rows),
          "ISCreateGeneral");
    check(ISCreateStride(comm, local_rows, first_row, 1, &columns), "ISCreateStride");
    check(MatCreateSubMatrix(K, rows, columns, MAT_INITIAL_MATRIX, &supported_rows),
          "MatCreateSubMatrix");
  }
  // K_ff with the supported rows and columns replaced by `scale` on the diagonal: a diagonal of
  // the size of K's keeps the operator's spectrum (and the AMG's smoothers) undisturbed.
  double scale = 1.0;
  {
    OwnedVec diagonal;
    check(MatCreateVecs(K, &diagonal, nullptr), "MatCreateVecs");
    check(MatGetDiagonal(K, diagonal), "MatGetDiagonal");
    PetscScalar sum = 0;
    PetscInt n = 0;
    check(VecSum(diagonal, &sum), "VecSum");
    check(VecGetSize(diagonal, &n), "VecGetSize");
    if (n > 0 && sum > 0) scale = sum / n;
  }
  check(MatZeroRowsColumns(K, static_cast<PetscInt>(fixed_rows.size()), fixed_rows.data(), scale,
                           nullptr, nullptr),
        "MatZeroRowsColumns");
  check(MatSetOption(K, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");

  OwnedKSP ksp;
  check(KSPCreate(comm, &ksp), "KSPCreate");
  check(KSPSetOperators(ksp, K, K), "KSPSetOperators");
  check(KSPSetType(ksp, KSPCG), "KSPSetType");
  // The tolerance is on the true residual ||b - K u||, not the preconditioned one, so it means
  // the same whatever the preconditioner.
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check(KSPSetTolerances(ksp, options.relative_tolerance, PETSC_DEFAULT, PETSC_DEFAULT,
                         options.max_iterations),
        "KSPSetTolerances");
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  if (options.preconditioner == "gamg") {
    check(PCSetType(pc, PCGAMG), "PCSetType");
  } else if (options.preconditioner == "hypre") {
    check(PCSetType(pc, PCHYPRE), "PCSetType");
    check(PCHYPRESetType(pc, "boomeramg"), "PCHYPRESetType");
  } else if (options.preconditioner == "lu") {
    check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
    check(KSPSetNormType(ksp, KSP_NORM_NONE), "KSPSetNormType");  // preonly computes no norm
    check(PCSetType(pc, PCLU), "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  } else {
    throw nurbs::InputError("unknown PETSc preconditioner '" + options.preconditioner +
                            "'; use gamg, hypre or lu");
  }
  check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
  check(KSPSetUp(ksp), "KSPSetUp");
  {
    KSPType ksp_type = nullptr;
    PCType pc_type = nullptr;
    check(KSPGetType(ksp, &ksp_type), "KSPGetType");
    check(PCGetType(pc, &pc_type), "PCGetType");
    result.preconditioner = std::string(ksp_type) + " + " + pc_type;
  }
  result.factorization_seconds = seconds_since(start);

  OwnedVec b, x, product, supported_product;
  check(MatCreateVecs(K, &x, &b), "MatCreateVecs");
  check(VecDuplicate(b, &product), "VecDuplicate");
  check(MatCreateVecs(supported_rows, nullptr, &supported_product), "MatCreateVecs");
  // Both gathered vectors have K's layout, so one scatter (to rank 0) serves them.
  OwnedScatter to_root;
  OwnedVec gathered;
  check(VecScatterCreateToZero(x, &to_root, &gathered), "VecScatterCreateToZero");
  auto gather = [&](Vec v) {
    check(VecScatterBegin(to_root, v, gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(to_root, v, gathered, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    Eigen::VectorXd global;
    if (rank == 0) {
      VecRead values(gathered);
      global.resize(dofs.num_dofs());
      for (int dof = 0; dof < dofs.num_dofs(); ++dof) global[dof] = values[petsc_row(dof)];
    }
    return global;
  };

  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    // The load vector of the serial code on every rank (surface and body integrals are cheap next
    // to K); each rank keeps its rows.
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    detail::check_load_finite(load, force);
    {
      VecWrite rhs(b);
      VecRead c(coupling);
      for (int node = 0; node < dofs.num_nodes(); ++node) {
        if (d.owner[static_cast<size_t>(node)] != rank) continue;
        for (int k = 0; k < dim; ++k) {
          const PetscInt i = petsc_row(node * dim + k) - first_row;
          rhs[i] = force[node * dim + k] - c[i];
        }
      }
      for (size_t k = 0; k < fixed_rows.size(); ++k)
        rhs[fixed_rows[k] - first_row] = scale * fixed_values[k];
    }
    check(KSPSolve(ksp, b, x), "KSPSolve");
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscInt iterations = 0;
    check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
    check(KSPGetIterationNumber(ksp, &iterations), "KSPGetIterationNumber");
    // The true residual ||b - K u|| / ||b||, reported: CG's recursively updated residual (the
    // one the tolerance stops on) drifts from it by rounding. Near 1e-12 the true one stays at
    // 1e-12..3e-11 on the shipped cases (restarting CG from the solution did not lower it:
    // that is the rounding floor of K u for these condition numbers).
    PetscReal b_norm = 0, r_norm = 0;
    check(MatMult(K, x, product), "MatMult");
    check(VecAYPX(product, -1.0, b), "VecAYPX");
    check(VecNorm(product, NORM_2, &r_norm), "VecNorm");
    check(VecNorm(b, NORM_2, &b_norm), "VecNorm");
    const double residual = b_norm > 0 ? r_norm / b_norm : r_norm;
    if (reason < 0)
      throw std::runtime_error(
          "load case '" + load.id + "': the PETSc solve (" + result.preconditioner +
          ") did not converge: " + KSPConvergedReasons[reason] + " after " +
          std::to_string(iterations) + " iterations, relative residual " +
          std::to_string(residual) +
          "; the stiffness matrix may be singular (parts not held by supports, patches that do "
          "not connect) or too ill-conditioned for the tolerance");
    // Supported DOFs exactly at their values (the solve has them to rounding).
    {
      VecWrite u(x);
      for (size_t k = 0; k < fixed_rows.size(); ++k) u[fixed_rows[k] - first_row] = fixed_values[k];
    }
    // K u of the unmodified K: free rows K_ff u_f + K_fc u_c = (zeroed K) u + coupling, supported
    // rows from the kept K_c.
    check(MatMult(K, x, product), "MatMult");
    check(VecAXPY(product, 1.0, coupling), "VecAXPY");
    check(MatMult(supported_rows, x, supported_product), "MatMult");
    {
      VecWrite internal(product);
      VecRead kept(supported_product);
      for (size_t k = 0; k < fixed_rows.size(); ++k)
        internal[fixed_rows[k] - first_row] = kept[static_cast<PetscInt>(k)];
    }
    Eigen::VectorXd displacement = gather(x);
    const Eigen::VectorXd internal = gather(product);
    LoadCaseResult out;
    RankError overflow;
    if (rank == 0) try {
        out = detail::load_case_result(problem, dofs, constraints, load, force,
                                       std::move(displacement), internal);
      } catch (const std::runtime_error& ex) {
        overflow = {ex.what(), false};
      }
    agree_on_error(comm, overflow);
    out.id = load.id;
    out.iterations = static_cast<int>(iterations);
    out.relative_residual = residual;
    out.solve_seconds = seconds_since(start);
    result.load_cases.push_back(std::move(out));
  }
  return result;
}
}  // namespace

StaticResult solve_static_petsc(const Problem& problem, const PetscSolverOptions& options) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    throw std::logic_error("solve_static_petsc needs a live analysis::PetscSession");
  // The ranks assemble element by element; the B-bar projection couples beyond one element.
  if (problem.volumetric == Volumetric::kBbar)
    throw nurbs::InputError(
        "\"volumetric\": \"bbar\" runs on the direct, CG and AMG solvers, not the distributed "
        "PETSc backend; use \"displacement\" there");
  return solve_on(PETSC_COMM_WORLD, problem, options);
}

StaticResult solve_static_amg(const Problem& problem, const PetscSolverOptions& options) {
  // PETSc (and with it MPI, as a singleton: no mpirun) starts at the first AMG solve and stays
  // up until the program ends: MPI cannot be initialised twice in one process.
  static const PetscSession session;
  StaticResult result = solve_on(PETSC_COMM_SELF, problem, options);
  result.ranks = 1;
  return result;
}

#endif

}  // namespace isospring::analysis
