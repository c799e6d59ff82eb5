"""Experiments of the JPDA chapter (Fisher & Casasent 1989).

* :mod:`~projtrack.experiments.jpda.optables`: instrumented counts; Tables IV-VI as data; the
  fast algorithm with one in-situ working vector; the savings factor past Table VI.
* :mod:`~projtrack.experiments.jpda.misprints`: evidence for Tables IV-VI's misprints; vector-growth readings.
* :mod:`~projtrack.experiments.jpda.sweeps`: a forward-backward sweep over the reachable MU words only.
* :mod:`~projtrack.experiments.jpda.crosschecks`: beta by Sec. II.C's rule, by permanents; the permanent
  from JPDA normalizers; clutter sweep; orders of the feasible events.
* :mod:`~projtrack.experiments.jpda.routing`: can one chirp route the products of Fig. 5?
* :mod:`~projtrack.experiments.jpda.equivalence`: fast beta methods against the enumeration.
* :mod:`~projtrack.experiments.jpda.analog`: beta errors of Fig. 5 with noisy detectors.
* :mod:`~projtrack.experiments.jpda.timing`: wall-clock scaling of the exact beta methods.
* :mod:`~projtrack.experiments.jpda.tracking`: crossing targets: JPDA and GNN against the truth.
"""

from __future__ import annotations

from .analog import ANALOG_TOLERANCE, analog_accuracy, analog_trial, median_interval
from .crosschecks import (
    beta_by_permanents,
    beta_literature_rule,
    clutter_sensitivity,
    event_orders,
    permanent_by_interpolation,
    permanent_rect,
)
from .equivalence import equivalence_study, equivalence_summary, equivalence_trial, normalization_summary
from .misprints import (
    RELATIVE_FALL,
    count_table_verdict,
    fast_count_readings,
    grows_geometrically,
    growth_readings,
    relative_growth_table,
    row_growth,
    multiplication_rule_table,
    multiplication_rules,
    misprint_evidence,
    ratio_fits,
    rule_fits,
    supported_value,
    table5_additions_proof,
    table5_additions_rule,
)
from .optables import (
    InSituRun,
    all_ones_mvm,
    beta_in_situ,
    count_grid,
    half_up,
    in_situ_study,
    in_situ_summary,
    instrumented_counts,
    parse_count_table,
    parse_ratio_table,
    savings,
    savings_orders,
    savings_paths,
    vector_growth,
)
from .routing import chirp_routing, routing_table, slot_by_diode
from .sweeps import SweepRun, beta_sweep_reachable, sweep_counts
from .timing import best_of, scaling_timings
from .tracking import (
    run_trackers,
    score_tracks,
    tracking_sampling,
    tracking_study,
    tracking_summary,
    tracking_trial,
)

__all__ = [
    "all_ones_mvm",
    "instrumented_counts",
    "count_grid",
    "parse_count_table",
    "parse_ratio_table",
    "half_up",
    "vector_growth",
    "InSituRun",
    "beta_in_situ",
    "in_situ_study",
    "in_situ_summary",
    "savings",
    "savings_paths",
    "savings_orders",
    "SweepRun",
    "beta_sweep_reachable",
    "sweep_counts",
    "fast_count_readings",
    "misprint_evidence",
    "count_table_verdict",
    "multiplication_rules",
    "rule_fits",
    "multiplication_rule_table",
    "table5_additions_rule",
    "table5_additions_proof",
    "ratio_fits",
    "supported_value",
    "grows_geometrically",
    "growth_readings",
    "relative_growth_table",
    "RELATIVE_FALL",
    "row_growth",
    "beta_literature_rule",
    "permanent_rect",
    "beta_by_permanents",
    "permanent_by_interpolation",
    "clutter_sensitivity",
    "event_orders",
    "chirp_routing",
    "slot_by_diode",
    "routing_table",
    "equivalence_trial",
    "equivalence_study",
    "equivalence_summary",
    "normalization_summary",
    "analog_trial",
    "analog_accuracy",
    "median_interval",
    "ANALOG_TOLERANCE",
    "best_of",
    "scaling_timings",
    "score_tracks",
    "run_trackers",
    "tracking_trial",
    "tracking_study",
    "tracking_summary",
    "tracking_sampling",
]

# The trackers on real pedestrians (TUD-Campus, TUD-Stadtmitte, shipped by motmetrics), scored
# with the CLEAR MOT and identity metrics, beside Stone Soup's JPDA with EHM.
from .motscore import (
    box_iou,
    centred_overlap,
    crossing_mot_table,
    crossing_mot_trial,
    mot_summary,
    score_arrays,
    score_points,
)
from .pedestrians import (
    detector_statistics,
    gt_model,
    motion_statistics,
    pedestrian_model,
    pedestrian_study,
    pedestrian_table,
    pedestrian_tolerances,
    draw_spread_tolerances,
    paired_mota_table,
    pedestrian_trial,
    run_difference,
    run_trackers_on,
    shipped_detections,
    shipped_model,
    shipped_trial,
    synthetic_detections,
)
from .pedplots import plot_association_times, plot_tracks_over_time
from .pedtiming import crowd_scan, scan_clusters, steady_state_innovation, stonesoup_ehm_beta, time_association
from .pedtracking import PedestrianModel, TrackRun, predicted_measurements, track_sequence

__all__ += [
    "box_iou",
    "centred_overlap",
    "mot_summary",
    "score_points",
    "score_arrays",
    "crossing_mot_trial",
    "crossing_mot_table",
    "motion_statistics",
    "detector_statistics",
    "pedestrian_model",
    "gt_model",
    "shipped_model",
    "synthetic_detections",
    "shipped_detections",
    "run_difference",
    "run_trackers_on",
    "pedestrian_trial",
    "shipped_trial",
    "pedestrian_study",
    "pedestrian_table",
    "pedestrian_tolerances",
    "draw_spread_tolerances",
    "paired_mota_table",
    "PedestrianModel",
    "TrackRun",
    "predicted_measurements",
    "track_sequence",
    "steady_state_innovation",
    "crowd_scan",
    "stonesoup_ehm_beta",
    "scan_clusters",
    "time_association",
    "plot_tracks_over_time",
    "plot_association_times",
]
