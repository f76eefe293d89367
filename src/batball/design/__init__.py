"""Bat design studies: a design space over a bat spec's values, the virtual tests as responses,
certification rules as constraints, sampling and a local search, and the best designs as bat
specs (``batball design STUDY.toml``; docs/design.md)."""

from batball.design.rules import RULES, Rule
from batball.design.run import DesignResult, evaluate_design, run_design_study
from batball.design.study import DesignStudy, design_study_from_dict, load_design_study

__all__ = [
    "RULES",
    "DesignResult",
    "DesignStudy",
    "Rule",
    "design_study_from_dict",
    "evaluate_design",
    "load_design_study",
    "run_design_study",
]
