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
// Where the DOFs of one solve live on the ranks of `comm` (distribute): each rank owns a
// contiguous range of PETSc nodes, block rows of `dim` DOFs.
struct RankLayout {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0, size = 1, dim = 0;
  Distribution d;
  int first_node = 0;
  PetscInt local_rows = 0, first_row = 0;

  PetscInt row(int dof) const {
    return static_cast<PetscInt>(d.petsc_node[static_cast<size_t>(dof / dim)]) * dim + dof % dim;
  }
  bool owns(int node) const { return d.owner[static_cast<size_t>(node)] == rank; }
};

RankLayout make_layout(MPI_Comm comm, const DofMap& dofs,
                       const detail::AssemblyStructure& structure) {
  RankLayout layout;
  layout.comm = comm;
  MPI_Comm_rank(comm, &layout.rank);
  MPI_Comm_size(comm, &layout.size);
  layout.dim = dofs.dofs_per_node();
  layout.d = distribute(structure, dofs.num_nodes(), layout.size);
  const auto r = static_cast<size_t>(layout.rank);
  layout.first_node = layout.d.node_start[r];
  const int owned_nodes = layout.d.node_start[r + 1] - layout.first_node;
  layout.local_rows = static_cast<PetscInt>(owned_nodes) * layout.dim;
  layout.first_row = static_cast<PetscInt>(layout.first_node) * layout.dim;
  return layout;
}

// K with this rank's rows (square, in `dim` x `dim` blocks), of `type`, before preallocation;
// PETSc's options database may still change the type.
void create_matrix(const RankLayout& layout, MatType type, OwnedMat& K) {
  check(MatCreate(layout.comm, &K), "MatCreate");
  check(MatSetSizes(K, layout.local_rows, layout.local_rows, PETSC_DETERMINE, PETSC_DETERMINE),
        "MatSetSizes");
  check(MatSetBlockSize(K, layout.dim), "MatSetBlockSize");
  check(MatSetType(K, type), "MatSetType");
  check(MatSetFromOptions(K), "MatSetFromOptions");
}

// One process (the serial AMG solver): the serial assembler on all threads, copied into PETSc's
// AIJ as full rows; the PETSc numbering is the DofMap's (one rank owns every node, in order).
// Element by element through MatSetValuesBlocked took twice as long on one thread.
void assemble_on_one_rank(const Problem& problem, const DofMap& dofs, const RankLayout& layout,
                          OwnedMat& K) {
  const Eigen::SparseMatrix<double> upper = assemble_stiffness(problem, dofs);
  Eigen::SparseMatrix<double, Eigen::RowMajor> full = upper.selfadjointView<Eigen::Upper>();
  full.makeCompressed();
  const std::vector<PetscInt> rows(full.outerIndexPtr(), full.outerIndexPtr() + full.rows() + 1);
  const std::vector<PetscInt> columns(full.innerIndexPtr(), full.innerIndexPtr() + full.nonZeros());
  create_matrix(layout, MATSEQAIJ, K);
  check(MatSeqAIJSetPreallocationCSR(K, rows.data(), columns.data(), full.valuePtr()),
        "MatSeqAIJSetPreallocationCSR");
}

// Several ranks: each assembles its own elements with the serial kernel; entries of rows owned
// by other ranks are stashed by PETSc and sent in MatAssemblyBegin/End. An element error stops
// this rank's loop and is shared after the assembly (`error`).
void assemble_on_ranks(const Problem& problem, const detail::AssemblyStructure& structure,
                       const RankLayout& layout, OwnedMat& K, RankError& error) {
  std::vector<PetscInt> diagonal, off_diagonal;
  count_nonzeros(structure, layout.d, layout.rank, diagonal, off_diagonal);
  create_matrix(layout, MATAIJ, K);
  check(MatXAIJSetPreallocation(K, layout.dim, diagonal.data(), off_diagonal.data(), nullptr,
                                nullptr),
        "MatXAIJSetPreallocation");
  const detail::ElementStiffness kernel(problem, structure);
  detail::QuadraturePoint point;
  Eigen::MatrixXd local;
  std::vector<PetscInt> blocks;
  const auto r = static_cast<size_t>(layout.rank);
  for (int e = layout.d.element_start[r]; e < layout.d.element_start[r + 1]; ++e) {
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
          layout.d.petsc_node[static_cast<size_t>(structure.nodes[static_cast<size_t>(k)])]);
    const PetscInt n = static_cast<PetscInt>(blocks.size());
    // `local` is symmetric, so its column-major storage is the row-major array PETSc reads.
    check(MatSetValuesBlocked(K, n, blocks.data(), n, blocks.data(), local.data(), ADD_VALUES),
          "MatSetValuesBlocked");
  }
}

// Rigid-body near-null space from the control points: control values a + w x X_a give exactly
// the rigid motion a + w x x (the NURBS basis reproduces the geometry), so these are the exact
// null space of the unsupported K, which smoothed aggregation needs for elasticity.
void attach_rigid_body_modes(Mat K, const DofMap& dofs, const RankLayout& layout) {
  OwnedVec coordinates;
  check(VecCreateMPI(layout.comm, layout.local_rows, PETSC_DETERMINE, &coordinates),
        "VecCreateMPI");
  check(VecSetBlockSize(coordinates, layout.dim), "VecSetBlockSize");
  {
    VecWrite x(coordinates);
    const auto& positions = dofs.node_positions();
    for (int node = 0; node < dofs.num_nodes(); ++node)
      if (layout.owns(node))
        for (int c = 0; c < layout.dim; ++c)
          x[(layout.d.petsc_node[static_cast<size_t>(node)] - layout.first_node) * layout.dim + c] =
              positions[static_cast<size_t>(node)][c];
  }
  OwnedNullSpace rigid;
  check(MatNullSpaceCreateRigidBody(coordinates, &rigid), "MatNullSpaceCreateRigidBody");
  check(MatSetNearNullSpace(K, rigid), "MatSetNearNullSpace");
}

// The supports taken out of K: the prescribed rows this rank owns (increasing) and their values,
// K u_c (`coupling`: its free rows K_fc u_c go to the right-hand side, its supported rows are
// K_cc u_c), the supported rows of the unmodified K (K_c, few rows, for the reactions K u - f)
// and the diagonal value the supported rows and columns of K are replaced by.
struct EliminatedSupports {
  std::vector<PetscInt> rows;
  std::vector<double> values;
  OwnedVec prescribed, coupling;
  OwnedMat supported_rows;
  double scale = 1.0;
};

void eliminate_supports(Mat K, const Constraints& constraints, const RankLayout& layout,
                        EliminatedSupports& supports) {
  for (size_t k = 0; k < constraints.dofs.size(); ++k) {
    const int dof = constraints.dofs[k];
    if (!layout.owns(dof / layout.dim)) continue;
    supports.rows.push_back(layout.row(dof));
    supports.values.push_back(constraints.values[k]);
  }
  check(MatCreateVecs(K, &supports.prescribed, &supports.coupling), "MatCreateVecs");
  check(VecSet(supports.prescribed, 0.0), "VecSet");
  {
    VecWrite u(supports.prescribed);
    for (size_t k = 0; k < supports.rows.size(); ++k)
      u[supports.rows[k] - layout.first_row] = supports.values[k];
  }
  check(MatMult(K, supports.prescribed, supports.coupling), "MatMult");
  {
    OwnedIS rows, columns;
    check(ISCreateGeneral(layout.comm, static_cast<PetscInt>(supports.rows.size()),
                          supports.rows.data(), PETSC_COPY_VALUES, &rows),
          "ISCreateGeneral");
    check(ISCreateStride(layout.comm, layout.local_rows, layout.first_row, 1, &columns),
          "ISCreateStride");
    check(MatCreateSubMatrix(K, rows, columns, MAT_INITIAL_MATRIX, &supports.supported_rows),
          "MatCreateSubMatrix");
  }
  // K_ff with the supported rows and columns replaced by `scale` on the diagonal: a diagonal of
  // the size of K's keeps the operator's spectrum (and the AMG's smoothers) undisturbed.
  {
    OwnedVec diagonal;
    check(MatCreateVecs(K, &diagonal, nullptr), "MatCreateVecs");
    check(MatGetDiagonal(K, diagonal), "MatGetDiagonal");
    PetscScalar sum = 0;
    PetscInt n = 0;
    check(VecSum(diagonal, &sum), "VecSum");
    check(VecGetSize(diagonal, &n), "VecGetSize");
    if (n > 0 && sum > 0) supports.scale = sum / n;
  }
  check(MatZeroRowsColumns(K, static_cast<PetscInt>(supports.rows.size()), supports.rows.data(),
                           supports.scale, nullptr, nullptr),
        "MatZeroRowsColumns");
  check(MatSetOption(K, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
}

// CG with the chosen preconditioner (or MUMPS' LU alone), set up; returns "ksp + pc" as PETSc
// names them after its options database had its say.
std::string set_up_krylov_solver(MPI_Comm comm, Mat K, const PetscSolverOptions& options,
                                 OwnedKSP& ksp) {
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
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  check(KSPGetType(ksp, &ksp_type), "KSPGetType");
  check(PCGetType(pc, &pc_type), "PCGetType");
  return std::string(ksp_type) + " + " + pc_type;
}

// The vectors of the load-case solves, and one scatter to rank 0 that serves every vector of K's
// layout (the solution and K u).
struct SolveVectors {
  OwnedVec b, x, product, supported_product, gathered;
  OwnedScatter to_root;
};

void create_solve_vectors(Mat K, const EliminatedSupports& supports, SolveVectors& v) {
  check(MatCreateVecs(K, &v.x, &v.b), "MatCreateVecs");
  check(VecDuplicate(v.b, &v.product), "VecDuplicate");
  check(MatCreateVecs(supports.supported_rows, nullptr, &v.supported_product), "MatCreateVecs");
  check(VecScatterCreateToZero(v.x, &v.to_root, &v.gathered), "VecScatterCreateToZero");
}

// `values` (K's layout) on rank 0 in the DofMap's numbering; empty on the other ranks.
Eigen::VectorXd gather_to_root(SolveVectors& v, Vec values, const DofMap& dofs,
                               const RankLayout& layout) {
  check(VecScatterBegin(v.to_root, values, v.gathered, INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterBegin");
  check(VecScatterEnd(v.to_root, values, v.gathered, INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterEnd");
  Eigen::VectorXd global;
  if (layout.rank == 0) {
    VecRead gathered(v.gathered);
    global.resize(dofs.num_dofs());
    for (int dof = 0; dof < dofs.num_dofs(); ++dof) global[dof] = gathered[layout.row(dof)];
  }
  return global;
}

// b = f - K u_c on the free rows this rank owns, scale * u_c on the supported ones.
void fill_right_hand_side(const Eigen::VectorXd& force, const DofMap& dofs,
                          const RankLayout& layout, const EliminatedSupports& supports, Vec b) {
  VecWrite rhs(b);
  VecRead c(supports.coupling);
  for (int node = 0; node < dofs.num_nodes(); ++node) {
    if (!layout.owns(node)) continue;
    for (int k = 0; k < layout.dim; ++k) {
      const PetscInt i = layout.row(node * layout.dim + k) - layout.first_row;
      rhs[i] = force[node * layout.dim + k] - c[i];
    }
  }
  for (size_t k = 0; k < supports.rows.size(); ++k)
    rhs[supports.rows[k] - layout.first_row] = supports.scale * supports.values[k];
}

// KSPSolve with its outcome: iterations and the true relative residual ||b - K u|| / ||b||,
// reported because CG's recursively updated residual (the one the tolerance stops on) drifts
// from it by rounding. Near 1e-12 the true one stays at 1e-12..3e-11 on the shipped cases
// (restarting CG from the solution did not lower it: that is the rounding floor of K u for
// these condition numbers). A solve that did not converge is an error naming the likely cause.
void solve_and_check(KSP ksp, Mat K, SolveVectors& v, const std::string& load_id,
                     const std::string& solver, LoadCaseResult& out) {
  check(KSPSolve(ksp, v.b, v.x), "KSPSolve");
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscInt iterations = 0;
  check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
  check(KSPGetIterationNumber(ksp, &iterations), "KSPGetIterationNumber");
  PetscReal b_norm = 0, r_norm = 0;
  check(MatMult(K, v.x, v.product), "MatMult");
  check(VecAYPX(v.product, -1.0, v.b), "VecAYPX");
  check(VecNorm(v.product, NORM_2, &r_norm), "VecNorm");
  check(VecNorm(v.b, NORM_2, &b_norm), "VecNorm");
  const double residual = b_norm > 0 ? r_norm / b_norm : r_norm;
  if (reason < 0)
    throw std::runtime_error(
        "load case '" + load_id + "': the PETSc solve (" + solver +
        ") did not converge: " + KSPConvergedReasons[reason] + " after " +
        std::to_string(iterations) + " iterations, relative residual " + std::to_string(residual) +
        "; the stiffness matrix may be singular (parts not held by supports, patches that do "
        "not connect) or too ill-conditioned for the tolerance");
  out.iterations = static_cast<int>(iterations);
  out.relative_residual = residual;
}

// K u of the unmodified K into v.product: free rows K_ff u_f + K_fc u_c = (zeroed K) u +
// coupling, supported rows from the kept K_c. Sets the supported DOFs of u exactly to their
// values first (the solve has them to rounding).
void internal_force(Mat K, const RankLayout& layout, const EliminatedSupports& supports,
                    SolveVectors& v) {
  {
    VecWrite u(v.x);
    for (size_t k = 0; k < supports.rows.size(); ++k)
      u[supports.rows[k] - layout.first_row] = supports.values[k];
  }
  check(MatMult(K, v.x, v.product), "MatMult");
  check(VecAXPY(v.product, 1.0, supports.coupling), "VecAXPY");
  check(MatMult(supports.supported_rows, v.x, v.supported_product), "MatMult");
  VecWrite internal(v.product);
  VecRead kept(v.supported_product);
  for (size_t k = 0; k < supports.rows.size(); ++k)
    internal[supports.rows[k] - layout.first_row] = kept[static_cast<PetscInt>(k)];
}

// The solve of solve_static_petsc on the ranks of `comm`: PETSC_COMM_WORLD for the distributed
// backend, PETSC_COMM_SELF for the serial AMG solver (solve_static_amg). Every rank validates and
// numbers the same problem, so input errors are found by all alike; the load vectors are the
// serial code's on every rank (surface and body integrals are cheap next to K), each rank keeping
// its rows; the results are assembled on rank 0.
StaticResult solve_on(MPI_Comm comm, const Problem& problem, const PetscSolverOptions& options) {
  const ThreadScope threads(options.threads);
  const SupportedProblem supported = number_and_support(problem);
  const DofMap& dofs = supported.dofs;
  const Constraints& constraints = supported.constraints;
  const detail::AssemblyStructure structure(problem, dofs, /*with_pattern=*/false);
  const RankLayout layout = make_layout(comm, dofs, structure);

  StaticResult result;
  result.dofs = dofs.num_dofs();
  result.ranks = layout.size;
  auto start = std::chrono::steady_clock::now();
  OwnedMat K;
  RankError error;
  if (layout.size == 1)
    assemble_on_one_rank(problem, dofs, layout, K);
  else
    assemble_on_ranks(problem, structure, layout, K, error);
  check(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  agree_on_error(comm, error);
  result.assembly_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  attach_rigid_body_modes(K, dofs, layout);
  EliminatedSupports supports;
  eliminate_supports(K, constraints, layout, supports);
  OwnedKSP ksp;
  result.preconditioner = set_up_krylov_solver(comm, K, options, ksp);
  result.factorization_seconds = seconds_since(start);

  SolveVectors vectors;
  create_solve_vectors(K, supports, vectors);
  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    detail::check_load_finite(load, force);
    fill_right_hand_side(force, dofs, layout, supports, vectors.b);
    LoadCaseResult solved;
    solve_and_check(ksp, K, vectors, load.id, result.preconditioner, solved);
    internal_force(K, layout, supports, vectors);
    Eigen::VectorXd displacement = gather_to_root(vectors, vectors.x, dofs, layout);
    const Eigen::VectorXd internal = gather_to_root(vectors, vectors.product, dofs, layout);
    LoadCaseResult out;
    RankError overflow;
    if (layout.rank == 0) try {
        out = detail::load_case_result(problem, dofs, constraints, load, force,
                                       std::move(displacement), internal);
      } catch (const std::runtime_error& ex) {
        overflow = {ex.what(), false};
      }
    agree_on_error(comm, overflow);
    out.id = load.id;
    out.iterations = solved.iterations;
    out.relative_residual = solved.relative_residual;
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
