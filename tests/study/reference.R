# Reference values for tests/study from R (Debian r-base-core): Rscript reference.R CORPUS OUT
# CORPUS: id,group,value (group x or y). OUT: one row per id, NA where a test does not apply.
# Every p-value is R's default (wilcox.test / shapiro.test of this R version).
args <- commandArgs(trailingOnly = TRUE)
corpus <- read.csv(args[1], colClasses = c("integer", "character", "numeric"))
fmt <- function(v) if (is.null(v) || is.na(v)) "NA" else sprintf("%.17g", v)
sw <- function(v) {
  if (length(v) < 3 || length(v) > 5000 || diff(range(v)) < 1e-10) return(c(NA, NA))
  r <- shapiro.test(v)
  c(unname(r$statistic), r$p.value)
}
out <- c("id,r_version,sw_x_w,sw_x_p,sw_y_w,sw_y_p,paired_v,paired_p,unpaired_w,unpaired_p")
for (id in sort(unique(corpus$id))) {
  x <- corpus$value[corpus$id == id & corpus$group == "x"]
  y <- corpus$value[corpus$id == id & corpus$group == "y"]
  swx <- sw(x)
  swy <- sw(y)
  pv <- c(NA, NA)
  if (length(x) == length(y) && any(x != y)) {
    r <- suppressWarnings(wilcox.test(x, y, paired = TRUE))
    pv <- c(unname(r$statistic), r$p.value)
  }
  uw <- c(NA, NA)
  if (length(unique(c(x, y))) > 1) {
    r <- suppressWarnings(wilcox.test(x, y))
    uw <- c(unname(r$statistic), r$p.value)
  }
  out <- c(out, paste(id, paste0(R.version$major, ".", R.version$minor),
                      fmt(swx[1]), fmt(swx[2]), fmt(swy[1]), fmt(swy[2]),
                      fmt(pv[1]), fmt(pv[2]), fmt(uw[1]), fmt(uw[2]), sep = ","))
}
writeLines(out, args[2])
