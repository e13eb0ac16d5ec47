#!/usr/bin/env bash
# The test files moved into folders that mirror the packages (tests/<package>/test_<rest>.py).
# Replay from the repository's root after merging the branches that edit tests.
set -euo pipefail
git mv tests/test_allocation.py tests/allocation/test_allocator.py
git mv tests/test_allocation_authority.py tests/allocation/test_authority.py
git mv tests/test_allocation_extremes.py tests/allocation/test_extremes.py
git mv tests/test_allocation_isp.py tests/allocation/test_isp.py
git mv tests/test_allocation_series.py tests/allocation/test_series.py
git mv tests/test_allocation_state_input.py tests/allocation/test_state_input.py
git mv tests/test_allocation_swarms.py tests/allocation/test_swarms.py
git mv tests/test_cantilever.py tests/dynamics/test_cantilever.py
git mv tests/test_cli.py tests/cli/test_commands.py
git mv tests/test_cli_alternatives.py tests/cli/test_alternatives.py
git mv tests/test_cli_burn.py tests/cli/test_burn.py
git mv tests/test_cli_common.py tests/cli/test_common.py
git mv tests/test_cli_common_options.py tests/cli/test_common_options.py
git mv tests/test_cli_deorbit.py tests/cli/test_deorbit.py
git mv tests/test_cli_detumble.py tests/cli/test_detumble.py
git mv tests/test_cli_failures.py tests/cli/test_failures.py
git mv tests/test_cli_manoeuvres.py tests/cli/test_manoeuvres.py
git mv tests/test_cli_matrix.py tests/cli/test_matrix.py
git mv tests/test_cli_montecarlo.py tests/cli/test_montecarlo.py
git mv tests/test_cli_montecarlo_statistics.py tests/cli/test_montecarlo_statistics.py
git mv tests/test_cli_output.py tests/cli/test_output.py
git mv tests/test_cli_placement.py tests/cli/test_placement.py
git mv tests/test_cli_reproduce.py tests/cli/test_reproduce.py
git mv tests/test_cli_simulation.py tests/cli/test_simulation.py
git mv tests/test_cli_slew.py tests/cli/test_slew.py
git mv tests/test_cli_transfer.py tests/cli/test_transfer.py
git mv tests/test_cli_worstcase.py tests/cli/test_worstcase.py
git mv tests/test_config.py tests/config/test_problem.py
git mv tests/test_config_checks.py tests/config/test_checks.py
git mv tests/test_config_corpus.py tests/config/test_corpus.py
git mv tests/test_config_environment.py tests/config/test_environment.py
git mv tests/test_config_files.py tests/config/test_files.py
git mv tests/test_config_json_schema.py tests/config/test_json_schema.py
git mv tests/test_config_limits.py tests/config/test_limits.py
git mv tests/test_config_loader.py tests/config/test_loader.py
git mv tests/test_config_realism.py tests/config/test_realism.py
git mv tests/test_config_runs.py tests/config/test_runs.py
git mv tests/test_config_segments.py tests/config/test_segments.py
git mv tests/test_config_suggestions.py tests/config/test_suggestions.py
git mv tests/test_config_varied.py tests/config/test_varied.py
git mv tests/test_ctrl_c_in_solves.py tests/slews/test_ctrl_c_in_solves.py
git mv tests/test_environment_gravity.py tests/environment/test_gravity.py
git mv tests/test_environment_magnetic.py tests/environment/test_magnetic.py
git mv tests/test_environment_orbit.py tests/environment/test_orbit.py
git mv tests/test_environment_panels.py tests/environment/test_panels.py
git mv tests/test_environment_torques.py tests/environment/test_torques.py
git mv tests/test_guidance_limits.py tests/guidance/test_limits.py
git mv tests/test_linearize.py tests/dynamics/test_linearize.py
git mv tests/test_model.py tests/dynamics/test_model.py
git mv tests/test_model_attitude.py tests/dynamics/test_attitude.py
git mv tests/test_model_parameters.py tests/dynamics/test_parameters.py
git mv tests/test_orbit_atmosphere.py tests/orbit/test_atmosphere.py
git mv tests/test_orbit_ballistic.py tests/orbit/test_ballistic.py
git mv tests/test_orbit_deorbit.py tests/orbit/test_deorbit.py
git mv tests/test_orbit_elements.py tests/orbit/test_elements.py
git mv tests/test_orbit_lifetime.py tests/orbit/test_lifetime.py
git mv tests/test_orbit_lifetime_mc.py tests/orbit/test_lifetime_mc.py
git mv tests/test_orbit_lifetime_msis.py tests/orbit/test_lifetime_msis.py
git mv tests/test_orbit_propulsion.py tests/orbit/test_propulsion.py
git mv tests/test_orbit_swarm_size.py tests/orbit/test_swarm_size.py
git mv tests/test_orbit_transfer.py tests/orbit/test_transfer.py
git mv tests/test_orbit_transfer_averaged.py tests/orbit/test_transfer_averaged.py
git mv tests/test_orbit_transfer_guidance.py tests/orbit/test_transfer_guidance.py
git mv tests/test_orbit_transfer_ocp.py tests/orbit/test_transfer_ocp.py
git mv tests/test_orbit_transfer_thrust.py tests/orbit/test_transfer_thrust.py
git mv tests/test_parallel.py tests/parallel/test_map.py
git mv tests/test_plots.py tests/plots/test_figures.py
git mv tests/test_plots_placement.py tests/plots/test_placement.py
git mv tests/test_plots_scale.py tests/plots/test_scale.py
git mv tests/test_plots_statistics.py tests/plots/test_statistics.py
git mv tests/test_plots_thrust.py tests/plots/test_thrust.py
git mv tests/test_propulsion_series.py tests/allocation/test_propulsion_series.py
git mv tests/test_report_campaign_dataset.py tests/store/test_campaign_dataset.py
git mv tests/test_report_campaign_folder.py tests/store/test_campaign_folder.py
git mv tests/test_report_common.py tests/report/test_common.py
git mv tests/test_report_describe.py tests/report/test_describe.py
git mv tests/test_report_design.py tests/report/test_design.py
git mv tests/test_report_folders.py tests/store/test_folders.py
git mv tests/test_report_mission.py tests/report/test_mission.py
git mv tests/test_report_worstcase.py tests/report/test_worstcase.py
git mv tests/test_reproduce.py tests/workflows/test_reproduce_quick.py
git mv tests/test_robust_analysis.py tests/robust/test_analysis.py
git mv tests/test_robust_binding.py tests/robust/test_binding.py
git mv tests/test_robust_body_weights.py tests/robust/test_body_weights.py
git mv tests/test_robust_classical.py tests/robust/test_classical.py
git mv tests/test_robust_controller.py tests/robust/test_controller.py
git mv tests/test_robust_design.py tests/robust/test_design.py
git mv tests/test_robust_hinf.py tests/robust/test_hinf.py
git mv tests/test_robust_interconnect.py tests/robust/test_interconnect.py
git mv tests/test_robust_margins.py tests/robust/test_margins.py
git mv tests/test_robust_mu.py tests/robust/test_mu.py
git mv tests/test_robust_mu_bounds.py tests/robust/test_mu_bounds.py
git mv tests/test_robust_musyn.py tests/robust/test_musyn.py
git mv tests/test_robust_parametric.py tests/robust/test_parametric.py
git mv tests/test_robust_parametric_synthesis.py tests/robust/test_parametric_synthesis.py
git mv tests/test_robust_performance_search.py tests/robust/test_performance_search.py
git mv tests/test_robust_reduce.py tests/robust/test_reduce.py
git mv tests/test_robust_reference_scaling.py tests/robust/test_reference_scaling.py
git mv tests/test_robust_requirements.py tests/robust/test_requirements.py
git mv tests/test_robust_requirements_design.py tests/robust/test_requirements_design.py
git mv tests/test_robust_uncertainty.py tests/robust/test_uncertainty.py
git mv tests/test_robust_weights.py tests/robust/test_weights.py
git mv tests/test_simulation.py tests/simulation/test_closed_loop.py
git mv tests/test_simulation_batched.py tests/simulation/test_batched.py
git mv tests/test_simulation_burn.py tests/simulation/test_burn.py
git mv tests/test_simulation_compiled.py tests/simulation/test_compiled.py
git mv tests/test_simulation_detumble.py tests/simulation/test_detumble.py
git mv tests/test_simulation_detumble_full_ocp.py tests/simulation/test_detumble_full_ocp.py
git mv tests/test_simulation_detumble_ocp.py tests/simulation/test_detumble_ocp.py
git mv tests/test_simulation_engines.py tests/simulation/test_engines.py
git mv tests/test_simulation_environment.py tests/simulation/test_environment.py
git mv tests/test_simulation_estimation.py tests/simulation/test_estimation.py
git mv tests/test_simulation_monte_carlo.py tests/campaigns/test_monte_carlo.py
git mv tests/test_simulation_noise.py tests/simulation/test_noise.py
git mv tests/test_simulation_open_loop.py tests/simulation/test_open_loop.py
git mv tests/test_simulation_polhode.py tests/simulation/test_polhode.py
git mv tests/test_simulation_realism.py tests/simulation/test_realism.py
git mv tests/test_simulation_reference.py tests/guidance/test_reference.py
git mv tests/test_simulation_requirements.py tests/simulation/test_requirements.py
git mv tests/test_simulation_sampling.py tests/campaigns/test_sampling.py
git mv tests/test_simulation_segment_figures.py tests/simulation/test_segment_figures.py
git mv tests/test_simulation_sequence.py tests/guidance/test_sequence.py
git mv tests/test_simulation_statistics.py tests/campaigns/test_statistics.py
git mv tests/test_simulation_targets.py tests/guidance/test_targets.py
git mv tests/test_simulation_worst_case.py tests/campaigns/test_worst_case.py
git mv tests/test_slew.py tests/slews/test_profiles.py
git mv tests/test_slew_flexible.py tests/slews/test_flexible.py
git mv tests/test_slew_global.py tests/slews/test_global.py
git mv tests/test_slew_limits.py tests/slews/test_limits.py
git mv tests/test_slew_modal.py tests/slews/test_modal.py
git mv tests/test_slew_rigid_body.py tests/slews/test_rigid_body.py
git mv tests/test_slew_thruster_search.py tests/slews/test_thruster_search.py
git mv tests/test_studies_alternatives.py tests/studies/test_alternatives.py
git mv tests/test_studies_failure_authority.py tests/studies/test_failure_authority.py
git mv tests/test_studies_failure_cases.py tests/studies/test_failure_cases.py
git mv tests/test_studies_failure_records.py tests/studies/test_failure_records.py
git mv tests/test_studies_failure_sets.py tests/studies/test_failure_sets.py
git mv tests/test_studies_failures.py tests/studies/test_failures.py
git mv tests/test_studies_mission.py tests/studies/test_mission.py
git mv tests/test_studies_placement.py tests/studies/test_placement.py
git mv tests/test_studies_propellant_books.py tests/studies/test_propellant_books.py
git mv tests/test_workflows_allocate.py tests/workflows/test_allocate.py
git mv tests/test_workflows_alternatives.py tests/workflows/test_alternatives.py
git mv tests/test_workflows_budget.py tests/workflows/test_budget.py
git mv tests/test_workflows_burn.py tests/workflows/test_burn.py
git mv tests/test_workflows_campaign.py tests/workflows/test_campaign.py
git mv tests/test_workflows_compare.py tests/workflows/test_compare.py
git mv tests/test_workflows_controller.py tests/workflows/test_controller.py
git mv tests/test_workflows_deorbit.py tests/workflows/test_deorbit.py
git mv tests/test_workflows_design.py tests/workflows/test_design.py
git mv tests/test_workflows_detumble.py tests/workflows/test_detumble.py
git mv tests/test_workflows_failures.py tests/workflows/test_failures.py
git mv tests/test_workflows_margins.py tests/workflows/test_margins.py
git mv tests/test_workflows_mission.py tests/workflows/test_mission.py
git mv tests/test_workflows_model.py tests/workflows/test_model.py
git mv tests/test_workflows_montecarlo.py tests/workflows/test_montecarlo.py
git mv tests/test_workflows_placement.py tests/workflows/test_placement.py
git mv tests/test_workflows_reproduce.py tests/workflows/test_reproduce.py
git mv tests/test_workflows_simulate.py tests/workflows/test_simulate.py
git mv tests/test_workflows_slew.py tests/workflows/test_slew.py
git mv tests/test_workflows_synthesize.py tests/workflows/test_synthesize.py
git mv tests/test_workflows_transfer.py tests/workflows/test_transfer.py
git mv tests/test_workflows_worstcase.py tests/workflows/test_worstcase.py

# The old paths named in tests/, the guide, layout.md, pyproject's comments and .ci/run:
# this branch rewrote them in tests/ (but tests/test_valid_problems.py) and tests.md only;
# tests/ is searched again for what other branches wrote meanwhile.
files=$(grep -rlE 'tests/test_[a-z_]+[.]py' tests docs src pyproject.toml .ci benchmarks examples 2>/dev/null || true)
if [ -n "$files" ]; then
  sed -i -E \
    -e 's#tests/test_allocation[.]py\b#tests/allocation/test_allocator.py#g' \
    -e 's#tests/test_allocation_authority[.]py\b#tests/allocation/test_authority.py#g' \
    -e 's#tests/test_allocation_extremes[.]py\b#tests/allocation/test_extremes.py#g' \
    -e 's#tests/test_allocation_isp[.]py\b#tests/allocation/test_isp.py#g' \
    -e 's#tests/test_allocation_series[.]py\b#tests/allocation/test_series.py#g' \
    -e 's#tests/test_allocation_state_input[.]py\b#tests/allocation/test_state_input.py#g' \
    -e 's#tests/test_allocation_swarms[.]py\b#tests/allocation/test_swarms.py#g' \
    -e 's#tests/test_cantilever[.]py\b#tests/dynamics/test_cantilever.py#g' \
    -e 's#tests/test_cli[.]py\b#tests/cli/test_commands.py#g' \
    -e 's#tests/test_cli_alternatives[.]py\b#tests/cli/test_alternatives.py#g' \
    -e 's#tests/test_cli_burn[.]py\b#tests/cli/test_burn.py#g' \
    -e 's#tests/test_cli_common[.]py\b#tests/cli/test_common.py#g' \
    -e 's#tests/test_cli_common_options[.]py\b#tests/cli/test_common_options.py#g' \
    -e 's#tests/test_cli_deorbit[.]py\b#tests/cli/test_deorbit.py#g' \
    -e 's#tests/test_cli_detumble[.]py\b#tests/cli/test_detumble.py#g' \
    -e 's#tests/test_cli_failures[.]py\b#tests/cli/test_failures.py#g' \
    -e 's#tests/test_cli_manoeuvres[.]py\b#tests/cli/test_manoeuvres.py#g' \
    -e 's#tests/test_cli_matrix[.]py\b#tests/cli/test_matrix.py#g' \
    -e 's#tests/test_cli_montecarlo[.]py\b#tests/cli/test_montecarlo.py#g' \
    -e 's#tests/test_cli_montecarlo_statistics[.]py\b#tests/cli/test_montecarlo_statistics.py#g' \
    -e 's#tests/test_cli_output[.]py\b#tests/cli/test_output.py#g' \
    -e 's#tests/test_cli_placement[.]py\b#tests/cli/test_placement.py#g' \
    -e 's#tests/test_cli_reproduce[.]py\b#tests/cli/test_reproduce.py#g' \
    -e 's#tests/test_cli_simulation[.]py\b#tests/cli/test_simulation.py#g' \
    -e 's#tests/test_cli_slew[.]py\b#tests/cli/test_slew.py#g' \
    -e 's#tests/test_cli_transfer[.]py\b#tests/cli/test_transfer.py#g' \
    -e 's#tests/test_cli_worstcase[.]py\b#tests/cli/test_worstcase.py#g' \
    -e 's#tests/test_config[.]py\b#tests/config/test_problem.py#g' \
    -e 's#tests/test_config_checks[.]py\b#tests/config/test_checks.py#g' \
    -e 's#tests/test_config_corpus[.]py\b#tests/config/test_corpus.py#g' \
    -e 's#tests/test_config_environment[.]py\b#tests/config/test_environment.py#g' \
    -e 's#tests/test_config_files[.]py\b#tests/config/test_files.py#g' \
    -e 's#tests/test_config_json_schema[.]py\b#tests/config/test_json_schema.py#g' \
    -e 's#tests/test_config_limits[.]py\b#tests/config/test_limits.py#g' \
    -e 's#tests/test_config_loader[.]py\b#tests/config/test_loader.py#g' \
    -e 's#tests/test_config_realism[.]py\b#tests/config/test_realism.py#g' \
    -e 's#tests/test_config_runs[.]py\b#tests/config/test_runs.py#g' \
    -e 's#tests/test_config_segments[.]py\b#tests/config/test_segments.py#g' \
    -e 's#tests/test_config_suggestions[.]py\b#tests/config/test_suggestions.py#g' \
    -e 's#tests/test_config_varied[.]py\b#tests/config/test_varied.py#g' \
    -e 's#tests/test_ctrl_c_in_solves[.]py\b#tests/slews/test_ctrl_c_in_solves.py#g' \
    -e 's#tests/test_environment_gravity[.]py\b#tests/environment/test_gravity.py#g' \
    -e 's#tests/test_environment_magnetic[.]py\b#tests/environment/test_magnetic.py#g' \
    -e 's#tests/test_environment_orbit[.]py\b#tests/environment/test_orbit.py#g' \
    -e 's#tests/test_environment_panels[.]py\b#tests/environment/test_panels.py#g' \
    -e 's#tests/test_environment_torques[.]py\b#tests/environment/test_torques.py#g' \
    -e 's#tests/test_guidance_limits[.]py\b#tests/guidance/test_limits.py#g' \
    -e 's#tests/test_linearize[.]py\b#tests/dynamics/test_linearize.py#g' \
    -e 's#tests/test_model[.]py\b#tests/dynamics/test_model.py#g' \
    -e 's#tests/test_model_attitude[.]py\b#tests/dynamics/test_attitude.py#g' \
    -e 's#tests/test_model_parameters[.]py\b#tests/dynamics/test_parameters.py#g' \
    -e 's#tests/test_orbit_atmosphere[.]py\b#tests/orbit/test_atmosphere.py#g' \
    -e 's#tests/test_orbit_ballistic[.]py\b#tests/orbit/test_ballistic.py#g' \
    -e 's#tests/test_orbit_deorbit[.]py\b#tests/orbit/test_deorbit.py#g' \
    -e 's#tests/test_orbit_elements[.]py\b#tests/orbit/test_elements.py#g' \
    -e 's#tests/test_orbit_lifetime[.]py\b#tests/orbit/test_lifetime.py#g' \
    -e 's#tests/test_orbit_lifetime_mc[.]py\b#tests/orbit/test_lifetime_mc.py#g' \
    -e 's#tests/test_orbit_lifetime_msis[.]py\b#tests/orbit/test_lifetime_msis.py#g' \
    -e 's#tests/test_orbit_propulsion[.]py\b#tests/orbit/test_propulsion.py#g' \
    -e 's#tests/test_orbit_swarm_size[.]py\b#tests/orbit/test_swarm_size.py#g' \
    -e 's#tests/test_orbit_transfer[.]py\b#tests/orbit/test_transfer.py#g' \
    -e 's#tests/test_orbit_transfer_averaged[.]py\b#tests/orbit/test_transfer_averaged.py#g' \
    -e 's#tests/test_orbit_transfer_guidance[.]py\b#tests/orbit/test_transfer_guidance.py#g' \
    -e 's#tests/test_orbit_transfer_ocp[.]py\b#tests/orbit/test_transfer_ocp.py#g' \
    -e 's#tests/test_orbit_transfer_thrust[.]py\b#tests/orbit/test_transfer_thrust.py#g' \
    -e 's#tests/test_parallel[.]py\b#tests/parallel/test_map.py#g' \
    -e 's#tests/test_plots[.]py\b#tests/plots/test_figures.py#g' \
    -e 's#tests/test_plots_placement[.]py\b#tests/plots/test_placement.py#g' \
    -e 's#tests/test_plots_scale[.]py\b#tests/plots/test_scale.py#g' \
    -e 's#tests/test_plots_statistics[.]py\b#tests/plots/test_statistics.py#g' \
    -e 's#tests/test_plots_thrust[.]py\b#tests/plots/test_thrust.py#g' \
    -e 's#tests/test_propulsion_series[.]py\b#tests/allocation/test_propulsion_series.py#g' \
    -e 's#tests/test_report_campaign_dataset[.]py\b#tests/store/test_campaign_dataset.py#g' \
    -e 's#tests/test_report_campaign_folder[.]py\b#tests/store/test_campaign_folder.py#g' \
    -e 's#tests/test_report_common[.]py\b#tests/report/test_common.py#g' \
    -e 's#tests/test_report_describe[.]py\b#tests/report/test_describe.py#g' \
    -e 's#tests/test_report_design[.]py\b#tests/report/test_design.py#g' \
    -e 's#tests/test_report_folders[.]py\b#tests/store/test_folders.py#g' \
    -e 's#tests/test_report_mission[.]py\b#tests/report/test_mission.py#g' \
    -e 's#tests/test_report_worstcase[.]py\b#tests/report/test_worstcase.py#g' \
    -e 's#tests/test_reproduce[.]py\b#tests/workflows/test_reproduce_quick.py#g' \
    -e 's#tests/test_robust_analysis[.]py\b#tests/robust/test_analysis.py#g' \
    -e 's#tests/test_robust_binding[.]py\b#tests/robust/test_binding.py#g' \
    -e 's#tests/test_robust_body_weights[.]py\b#tests/robust/test_body_weights.py#g' \
    -e 's#tests/test_robust_classical[.]py\b#tests/robust/test_classical.py#g' \
    -e 's#tests/test_robust_controller[.]py\b#tests/robust/test_controller.py#g' \
    -e 's#tests/test_robust_design[.]py\b#tests/robust/test_design.py#g' \
    -e 's#tests/test_robust_hinf[.]py\b#tests/robust/test_hinf.py#g' \
    -e 's#tests/test_robust_interconnect[.]py\b#tests/robust/test_interconnect.py#g' \
    -e 's#tests/test_robust_margins[.]py\b#tests/robust/test_margins.py#g' \
    -e 's#tests/test_robust_mu[.]py\b#tests/robust/test_mu.py#g' \
    -e 's#tests/test_robust_mu_bounds[.]py\b#tests/robust/test_mu_bounds.py#g' \
    -e 's#tests/test_robust_musyn[.]py\b#tests/robust/test_musyn.py#g' \
    -e 's#tests/test_robust_parametric[.]py\b#tests/robust/test_parametric.py#g' \
    -e 's#tests/test_robust_parametric_synthesis[.]py\b#tests/robust/test_parametric_synthesis.py#g' \
    -e 's#tests/test_robust_performance_search[.]py\b#tests/robust/test_performance_search.py#g' \
    -e 's#tests/test_robust_reduce[.]py\b#tests/robust/test_reduce.py#g' \
    -e 's#tests/test_robust_reference_scaling[.]py\b#tests/robust/test_reference_scaling.py#g' \
    -e 's#tests/test_robust_requirements[.]py\b#tests/robust/test_requirements.py#g' \
    -e 's#tests/test_robust_requirements_design[.]py\b#tests/robust/test_requirements_design.py#g' \
    -e 's#tests/test_robust_uncertainty[.]py\b#tests/robust/test_uncertainty.py#g' \
    -e 's#tests/test_robust_weights[.]py\b#tests/robust/test_weights.py#g' \
    -e 's#tests/test_simulation[.]py\b#tests/simulation/test_closed_loop.py#g' \
    -e 's#tests/test_simulation_batched[.]py\b#tests/simulation/test_batched.py#g' \
    -e 's#tests/test_simulation_burn[.]py\b#tests/simulation/test_burn.py#g' \
    -e 's#tests/test_simulation_compiled[.]py\b#tests/simulation/test_compiled.py#g' \
    -e 's#tests/test_simulation_detumble[.]py\b#tests/simulation/test_detumble.py#g' \
    -e 's#tests/test_simulation_detumble_full_ocp[.]py\b#tests/simulation/test_detumble_full_ocp.py#g' \
    -e 's#tests/test_simulation_detumble_ocp[.]py\b#tests/simulation/test_detumble_ocp.py#g' \
    -e 's#tests/test_simulation_engines[.]py\b#tests/simulation/test_engines.py#g' \
    -e 's#tests/test_simulation_environment[.]py\b#tests/simulation/test_environment.py#g' \
    -e 's#tests/test_simulation_estimation[.]py\b#tests/simulation/test_estimation.py#g' \
    -e 's#tests/test_simulation_monte_carlo[.]py\b#tests/campaigns/test_monte_carlo.py#g' \
    -e 's#tests/test_simulation_noise[.]py\b#tests/simulation/test_noise.py#g' \
    -e 's#tests/test_simulation_open_loop[.]py\b#tests/simulation/test_open_loop.py#g' \
    -e 's#tests/test_simulation_polhode[.]py\b#tests/simulation/test_polhode.py#g' \
    -e 's#tests/test_simulation_realism[.]py\b#tests/simulation/test_realism.py#g' \
    -e 's#tests/test_simulation_reference[.]py\b#tests/guidance/test_reference.py#g' \
    -e 's#tests/test_simulation_requirements[.]py\b#tests/simulation/test_requirements.py#g' \
    -e 's#tests/test_simulation_sampling[.]py\b#tests/campaigns/test_sampling.py#g' \
    -e 's#tests/test_simulation_segment_figures[.]py\b#tests/simulation/test_segment_figures.py#g' \
    -e 's#tests/test_simulation_sequence[.]py\b#tests/guidance/test_sequence.py#g' \
    -e 's#tests/test_simulation_statistics[.]py\b#tests/campaigns/test_statistics.py#g' \
    -e 's#tests/test_simulation_targets[.]py\b#tests/guidance/test_targets.py#g' \
    -e 's#tests/test_simulation_worst_case[.]py\b#tests/campaigns/test_worst_case.py#g' \
    -e 's#tests/test_slew[.]py\b#tests/slews/test_profiles.py#g' \
    -e 's#tests/test_slew_flexible[.]py\b#tests/slews/test_flexible.py#g' \
    -e 's#tests/test_slew_global[.]py\b#tests/slews/test_global.py#g' \
    -e 's#tests/test_slew_limits[.]py\b#tests/slews/test_limits.py#g' \
    -e 's#tests/test_slew_modal[.]py\b#tests/slews/test_modal.py#g' \
    -e 's#tests/test_slew_rigid_body[.]py\b#tests/slews/test_rigid_body.py#g' \
    -e 's#tests/test_slew_thruster_search[.]py\b#tests/slews/test_thruster_search.py#g' \
    -e 's#tests/test_studies_alternatives[.]py\b#tests/studies/test_alternatives.py#g' \
    -e 's#tests/test_studies_failure_authority[.]py\b#tests/studies/test_failure_authority.py#g' \
    -e 's#tests/test_studies_failure_cases[.]py\b#tests/studies/test_failure_cases.py#g' \
    -e 's#tests/test_studies_failure_records[.]py\b#tests/studies/test_failure_records.py#g' \
    -e 's#tests/test_studies_failure_sets[.]py\b#tests/studies/test_failure_sets.py#g' \
    -e 's#tests/test_studies_failures[.]py\b#tests/studies/test_failures.py#g' \
    -e 's#tests/test_studies_mission[.]py\b#tests/studies/test_mission.py#g' \
    -e 's#tests/test_studies_placement[.]py\b#tests/studies/test_placement.py#g' \
    -e 's#tests/test_studies_propellant_books[.]py\b#tests/studies/test_propellant_books.py#g' \
    -e 's#tests/test_workflows_allocate[.]py\b#tests/workflows/test_allocate.py#g' \
    -e 's#tests/test_workflows_alternatives[.]py\b#tests/workflows/test_alternatives.py#g' \
    -e 's#tests/test_workflows_budget[.]py\b#tests/workflows/test_budget.py#g' \
    -e 's#tests/test_workflows_burn[.]py\b#tests/workflows/test_burn.py#g' \
    -e 's#tests/test_workflows_campaign[.]py\b#tests/workflows/test_campaign.py#g' \
    -e 's#tests/test_workflows_compare[.]py\b#tests/workflows/test_compare.py#g' \
    -e 's#tests/test_workflows_controller[.]py\b#tests/workflows/test_controller.py#g' \
    -e 's#tests/test_workflows_deorbit[.]py\b#tests/workflows/test_deorbit.py#g' \
    -e 's#tests/test_workflows_design[.]py\b#tests/workflows/test_design.py#g' \
    -e 's#tests/test_workflows_detumble[.]py\b#tests/workflows/test_detumble.py#g' \
    -e 's#tests/test_workflows_failures[.]py\b#tests/workflows/test_failures.py#g' \
    -e 's#tests/test_workflows_margins[.]py\b#tests/workflows/test_margins.py#g' \
    -e 's#tests/test_workflows_mission[.]py\b#tests/workflows/test_mission.py#g' \
    -e 's#tests/test_workflows_model[.]py\b#tests/workflows/test_model.py#g' \
    -e 's#tests/test_workflows_montecarlo[.]py\b#tests/workflows/test_montecarlo.py#g' \
    -e 's#tests/test_workflows_placement[.]py\b#tests/workflows/test_placement.py#g' \
    -e 's#tests/test_workflows_reproduce[.]py\b#tests/workflows/test_reproduce.py#g' \
    -e 's#tests/test_workflows_simulate[.]py\b#tests/workflows/test_simulate.py#g' \
    -e 's#tests/test_workflows_slew[.]py\b#tests/workflows/test_slew.py#g' \
    -e 's#tests/test_workflows_synthesize[.]py\b#tests/workflows/test_synthesize.py#g' \
    -e 's#tests/test_workflows_transfer[.]py\b#tests/workflows/test_transfer.py#g' \
    -e 's#tests/test_workflows_worstcase[.]py\b#tests/workflows/test_worstcase.py#g' \
    $files
fi
