# Reference for tests/sysid/diagnose/paired_test_test.cc from R's sandwich package (Debian
# r-cran-sandwich): Rscript newey_west.R SERIES OUT
# SERIES: id,lag,value (one series per id, its Bartlett lag). OUT: id,var_sum, the Newey-West
# variance of the series' sum, n^2 times NeweyWest's variance of the mean of lm(d ~ 1) (no
# prewhitening, no small-sample adjustment: the plain Bartlett estimator).
suppressPackageStartupMessages(library(sandwich))
args <- commandArgs(trailingOnly = TRUE)
series <- read.csv(args[1], colClasses = c("integer", "integer", "numeric"))
out <- c("id,var_sum")
for (id in sort(unique(series$id))) {
  d <- series$value[series$id == id]
  lag <- series$lag[series$id == id][1]
  # a lag beyond the series: R warns and uses the n lags there are, as paired_test.cc does
  v <- suppressWarnings(NeweyWest(lm(d ~ 1), lag = lag, prewhite = FALSE, adjust = FALSE))[1, 1]
  out <- c(out, paste(id, sprintf("%.17g", length(d)^2 * v), sep = ","))
}
writeLines(out, args[2])
