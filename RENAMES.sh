#!/bin/sh
# Result types renamed to the four words (Settings, Request, Result, Summary).
# Run once from a worktree root: the lines run in order, and two of them reuse a name
# another line has just freed (BurnSummary, DetumbleSummary), so a second run would
# rename again.
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
