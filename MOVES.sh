# tests/valid_problems.py: lp_authority -> lp_authority_Nm (posed in mN, takes and returns SI).
# A caller that passed thrust in mN and read mNm must now pass newtons (see tests/test_slew_limits.py).
sed -i -E 's/\blp_authority\b/lp_authority_Nm/g' tests/valid_problems.py tests/test_valid_problems.py tests/test_slew_limits.py
