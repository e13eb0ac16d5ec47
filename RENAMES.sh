#!/bin/sh
# Result types renamed to the four words (Settings, Request, Result, Summary).
# Run once from a worktree root: the lines run in order, and two of them reuse a name
# another line has just freed (BurnSummary, DetumbleSummary), so a second run would
# rename again. Afterwards run `ruff format` and `ruff check --fix` (import and __all__
# order); one f-string in robust/plant/_controller.py then needs splitting by hand (E501).
FILES=$(grep -rlE --include='*.py' --include='*.md' --include='*.toml' --include='*.yml' --include='*.txt' '[A-Za-z]' src tests docs examples benchmarks README.md mkdocs.yml 2>/dev/null)
# "Figures" that hold numbers: records in display units.
sed -i -E 's/\bBodyFigures\b/BodySummary/g' $FILES
sed -i -E 's/\bCampaignFigures\b/VerificationSummary/g' $FILES
sed -i -E 's/\bCandidateFigures\b/CandidateSummary/g' $FILES
sed -i -E 's/\bControllerFigures\b/ControllerSummary/g' $FILES
sed -i -E 's/\bFailureFigures\b/WorstFailureSummary/g' $FILES
sed -i -E 's/\bInputLayoutFigures\b/InputLayoutSummary/g' $FILES
sed -i -E 's/\bLayoutFigures\b/LayoutSummary/g' $FILES
sed -i -E 's/\bParetoFigures\b/ParetoPointSummary/g' $FILES
sed -i -E 's/\bScalingFigures\b/ScalingSummary/g' $FILES
sed -i -E 's/\bSegmentFigures\b/SegmentRunSummary/g' $FILES
sed -i -E 's/\bSolveFigures\b/MilpSolveSummary/g' $FILES
sed -i -E 's/\bSolverFigures\b/SolverSummary/g' $FILES
sed -i -E 's/\bSwarmFigures\b/SwarmSummary/g' $FILES
sed -i -E 's/\bWorstFigure\b/WorstValueSummary/g' $FILES
# "Record": what is written to JSON is a Summary; what identifies a campaign is its identity
# (as CaseIdentity); the controller file's content is the Controller.
sed -i -E 's/\bCampaignRecord\b/CampaignIdentity/g' $FILES
sed -i -E 's/\bCaseFailureRecord\b/CaseFailureSummary/g' $FILES
sed -i -E 's/\bControllerRecord\b/Controller/g' $FILES
sed -i -E 's/\bEventRecord\b/EventSummary/g' $FILES
sed -i -E 's/\bFailureCaseRecord\b/FailureCaseSummary/g' $FILES
sed -i -E 's/\bHoldingRecord\b/HoldingSummary/g' $FILES
sed -i -E 's/\bManoeuvreRecord\b/ManoeuvreRunSummary/g' $FILES
sed -i -E 's/\bRunRecord\b/SimulationSummary/g' $FILES
sed -i -E 's/\bSegmentRecord\b/SegmentPlanSummary/g' $FILES
# "Report": the job's summary.json; the run's own summary below it becomes a RunSummary.
sed -i -E 's/\bAlternativesReport\b/AlternativesSummary/g' $FILES
sed -i -E 's/\bBurnSummary\b/BurnRunSummary/g' $FILES
sed -i -E 's/\bBurnReport\b/BurnSummary/g' $FILES
sed -i -E 's/\bDetumbleSummary\b/DetumbleRunSummary/g' $FILES
sed -i -E 's/\bDetumbleReport\b/DetumbleSummary/g' $FILES
sed -i -E 's/\bDeorbitReport\b/DeorbitSummary/g' $FILES
# "Verdict", "Outcome", "Options".
sed -i -E 's/\bClosedLoopVerdict\b/ClosedLoopCheckSummary/g' $FILES
sed -i -E 's/\bRunVerdict\b/RunCheckSummary/g' $FILES
sed -i -E 's/\bCaseOutcome\b/CaseResult/g' $FILES
sed -i -E 's/\bSlewOptions\b/OptimalSlewSettings/g' $FILES

# Names two packages exported with two meanings: the lower one renamed, the front door
# (casadi_debris.X) keeps its own. These seds are scoped to the files that mean the lower one.
S=src/casadi_debris
# slews.SlewSummary (a profile's figures) -> ProfileSummary; casadi_debris.SlewSummary is the job's.
sed -i -E 's/\bSlewSummary\b/ProfileSummary/g' $S/slews/_profile.py $S/slews/__init__.py
# allocation.AllocationResult (one demand's thrusts) -> Allocation, beside BatchAllocation and
# SeriesAllocation; casadi_debris.AllocationResult is the job's.
sed -i -E 's/\bAllocationResult\b/Allocation/g' $S/allocation/*.py
sed -i -E 's/\bAllocationResult as Allocation\b/Allocation/; s/\ballocation\.AllocationResult\b/allocation.Allocation/g' $S/workflows/_allocate.py
# simulation.detumble.DetumbleResult -> DetumbleRunResult (beside DetumbleRunSummary) and its
# detumble() -> simulate_detumble() (as simulation.burn.simulate_burn); casadi_debris.detumble
# and casadi_debris.DetumbleResult are the job's.
sed -i -E 's/\bDetumbleResult\b/DetumbleRunResult/g' $S/simulation/detumble/*.py $S/plots/_detumble.py $S/report/_detumble.py $S/studies/mission.py $S/studies/propellant_books.py
sed -i -E 's/\bDetumbleResult as DetumbleRun\b/DetumbleRunResult as DetumbleRun/; s/\bsimulation\.detumble\.DetumbleResult\b/simulation.detumble.DetumbleRunResult/g' $S/workflows/_detumble.py
sed -i -E 's/^def detumble\(/def simulate_detumble(/' $S/simulation/detumble/_detumble.py
sed -i -E 's/^    detumble,$/    simulate_detumble,/; s/^    "detumble",$/    "simulate_detumble",/; s/:func:`detumble`/:func:`simulate_detumble`/' $S/simulation/detumble/__init__.py
sed -i -E 's/(from casadi_debris\.simulation\.detumble import .*)\bdetumble\b/\1simulate_detumble/; s/\bsimulation\.detumble\.detumble\b/simulation.detumble.simulate_detumble/g' $FILES
sed -i -E 's/(^|[^._a-z])detumble\(problem/\1simulate_detumble(problem/g' $S/studies/mission.py tests/test_studies_propellant_books.py tests/test_simulation_detumble.py tests/test_simulation_detumble_ocp.py
sed -i -E 's/^    detumble,$/    simulate_detumble,/' tests/test_simulation_detumble_ocp.py
# slews.simulate (the model under a given input) -> simulate_open_loop; casadi_debris.simulate
# is the job, simulation.simulate the closed loop.
sed -i -E 's/\bsimulate\b/simulate_open_loop/g' $S/slews/_profile.py $S/slews/_ocp_solution.py $S/slews/_modal_window.py $S/slews/__init__.py tests/test_slew_modal.py
# simulation.burn.burn_figures (numbers and series) -> burn_summary; report.burn_figures draws.
sed -i -E 's/\bburn_figures\b/burn_summary/g' $S/simulation/burn/_figures.py $S/simulation/burn/__init__.py tests/test_simulation_burn.py
sed -i -E 's/\bburn_figures as burn_figures_of\b/burn_summary/; s/\bburn_figures_of\(/burn_summary(/g' $S/workflows/_burn.py
# orbit.Burn (a retrograde burn the decay flies) -> RetrogradeBurn; orbit.transfer.Burn is a
# transfer's firing window.
sed -i -E 's/(^|[^"])\bBurn\b/\1RetrogradeBurn/g' $S/orbit/_lifetime.py $S/orbit/_deorbit.py $S/orbit/__init__.py tests/test_orbit_lifetime.py
sed -i -E 's/^    "Burn",$/    "RetrogradeBurn",/' $S/orbit/__init__.py
# simulation.simulate (one closed-loop run) -> simulate_closed_loop; casadi_debris.simulate is
# the job. Scoped to the files that import it from casadi_debris.simulation (in this tree).
SIM="src/casadi_debris/simulation/_run.py src/casadi_debris/workflows/_compare.py src/casadi_debris/workflows/_montecarlo.py src/casadi_debris/simulation/__init__.py src/casadi_debris/campaigns/_worst_case.py src/casadi_debris/campaigns/_monte_carlo.py tests/test_simulation_realism.py tests/test_workflows_compare.py tests/test_simulation_worst_case.py tests/test_simulation_compiled.py tests/test_simulation_environment.py tests/test_simulation_sequence.py tests/test_simulation_segment_figures.py tests/test_workflows_controller.py tests/test_simulation_burn.py tests/test_simulation.py tests/test_simulation_engines.py tests/test_simulation_batched.py docs/_scripts/realism_figures.py docs/_scripts/environment_figures.py docs/_scripts/manoeuvre_figure.py benchmarks/simulation.py"
sed -i -E 's/(^|[^._a-zA-Z"'"'"'])simulate\(/\1simulate_closed_loop(/g; s/^(\s+)simulate,$/\1simulate_closed_loop,/; s/(import .*)\bsimulate\b/\1simulate_closed_loop/; s/:func:`simulate`/:func:`simulate_closed_loop`/g' $SIM
sed -i -E 's/^    "simulate",$/    "simulate_closed_loop",/' $S/simulation/__init__.py
sed -i -E 's/\bsimulation\.simulate\b/simulation.simulate_closed_loop/g' $FILES
# Constants two packages exported with one name and two meanings.
sed -i -E 's/\bFORMAT_VERSION\b/CONTROLLER_FORMAT_VERSION/g' $S/robust/plant/_controller.py $S/robust/plant/__init__.py
sed -i -E 's/\bFORMAT_VERSION\b/DATASET_FORMAT_VERSION/g' $S/store/_campaign_dataset.py $S/store/__init__.py $S/campaigns/_dataset.py
sed -i -E 's/\bDEFAULT_PERIOD_S\b/DETUMBLE_PERIOD_S/g' $S/simulation/detumble/_detumble.py $S/simulation/detumble/__init__.py $S/workflows/_detumble.py
sed -i -E 's/\bDEFAULT_PERIOD_S\b/BURN_PERIOD_S/g' $S/simulation/burn/_burn.py $S/simulation/burn/__init__.py $S/workflows/_burn.py
# Two job summaries that did not end in Summary.
sed -i -E 's/\bComparison\b/CompareSummary/g' $FILES
sed -i -E 's/\bModelDescription\b/ModelSummary/g' $FILES
