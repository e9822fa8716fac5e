# The reference solver of pwsim's QP benchmark: R's quadprog (Goldfarb-Idnani dual active set,
# Turlach & Weingessel's Fortran; Debian r-cran-quadprog) on problems
#   minimise 1/2 x' P x + q' x   subject to   G x <= h
# read from the plain-text form that mca/qp_problem.h writes (WriteQpProblemText):
#   pwsim-qp-text/1                       first line
#   problem NAME n m                      then per problem five lines:
#   P: n*n numbers, row-major / q: n / G: m*n, row-major (absent when m = 0) / h: m
# quadprog's form is  min -d'b + 1/2 b'Db  s.t.  A'b >= b0,  so D = P, d = -q, A = -G', b0 = -h.
#
#   Rscript scripts/qp-quadprog.R IN OUT [BATCHES PER_BATCH]
#
# OUT gets one line per problem:
#   NAME STATUS OBJECTIVE SECONDS ITERATIONS x_1 ... x_n
# STATUS: optimal, infeasible (quadprog: "constraints are inconsistent") or error:<message
# with blanks as _>; OBJECTIVE 1/2 x'Px + q'x at quadprog's x (NA unless optimal); ITERATIONS
# quadprog's count of constraints added. SECONDS: with BATCHES > 0, the median over BATCHES
# batches of (time of PER_BATCH cold calls of solve.QP) / PER_BATCH, wall clock (Sys.time),
# inside this R process: R's start-up and the reading of IN are excluded; each call includes
# solve.QP's argument checks, the Cholesky factorisation of D (factorized = FALSE) and the
# solve. NA without timing (BATCHES = 0, the default).

suppressPackageStartupMessages(library(quadprog))

args <- commandArgs(trailingOnly = TRUE)
if (length(args) < 2) stop("usage: Rscript qp-quadprog.R IN OUT [BATCHES PER_BATCH]")
batches <- if (length(args) >= 3) as.integer(args[3]) else 0L
per_batch <- if (length(args) >= 4) as.integer(args[4]) else 1L
if (is.na(batches) || batches < 0 || is.na(per_batch) || per_batch < 1) {
  stop("BATCHES: expected an integer >= 0, PER_BATCH an integer >= 1")
}

lines <- readLines(args[1])
if (length(lines) < 1 || lines[1] != "pwsim-qp-text/1") {
  stop(paste0(args[1], ":1: expected the header 'pwsim-qp-text/1'"))
}
numbers <- function(k, count, what) {
  v <- if (count == 0) numeric(0) else scan(text = lines[k], quiet = TRUE)
  if (length(v) != count) {
    stop(sprintf("%s:%d: field '%s': expected %d numbers, got %d", args[1], k, what, count, length(v)))
  }
  v
}

out <- character(0)
k <- 2
while (k <= length(lines)) {
  head <- strsplit(lines[k], " ", fixed = TRUE)[[1]]
  if (length(head) != 4 || head[1] != "problem") {
    stop(sprintf("%s:%d: expected 'problem NAME n m'", args[1], k))
  }
  name <- head[2]
  n <- as.integer(head[3])
  m <- as.integer(head[4])
  P <- matrix(numbers(k + 1, n * n, "P"), n, n, byrow = TRUE)
  q <- numbers(k + 2, n, "q")
  G <- matrix(numbers(k + 3, m * n, "G"), m, n, byrow = TRUE)
  h <- numbers(k + 4, m, "h")
  k <- k + 5
  A <- -t(G)
  b0 <- -h
  solve_once <- function() solve.QP(Dmat = P, dvec = -q, Amat = A, bvec = b0, meq = 0)
  status <- "optimal"
  sol <- tryCatch(solve_once(), error = function(e) {
    msg <- conditionMessage(e)
    status <<- if (grepl("inconsistent", msg)) "infeasible" else paste0("error:", gsub("[[:space:]]+", "_", msg))
    NULL
  })
  seconds <- NA
  if (!is.null(sol) && batches > 0) {
    per_call <- numeric(batches)
    for (b in seq_len(batches)) {
      start <- Sys.time()
      for (i in seq_len(per_batch)) solve_once()
      per_call[b] <- as.numeric(difftime(Sys.time(), start, units = "secs")) / per_batch
    }
    seconds <- median(per_call)
  }
  if (is.null(sol)) {
    x <- rep(NA_real_, n)
    objective <- NA
    iterations <- NA
  } else {
    x <- sol$solution
    objective <- 0.5 * sum(x * (P %*% x)) + sum(q * x)
    iterations <- sol$iterations[1]
  }
  out <- c(out, paste(name, status, sprintf("%.17g", objective), sprintf("%.6e", seconds),
                      iterations, paste(sprintf("%.17g", x), collapse = " ")))
}
writeLines(out, args[2])
