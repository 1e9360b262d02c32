within Lib.Sub;
model Misplaced "its within names another package than its directory"
  Real x = time;
end Misplaced;
