within ;
package Lib "a directory package: its children in files of their own"
  constant Real two = 2;
end Lib;
