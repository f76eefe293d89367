"""Model assembly: what the virtual tests are built from, so that no test borrows another's
builders. Above the solvers and below the lab tests."""
