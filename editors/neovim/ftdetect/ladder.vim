" textladder: LDmicro ladder programs.
" *.ladder is the text form. .ld and .txt files are recognised by their first line only:
" most .ld files are linker scripts, most .txt files are text.
autocmd BufRead,BufNewFile *.ladder setlocal filetype=ladder
autocmd BufRead,BufNewFile *.ld
      \ if getline(1) =~# '^LDmicro export text' | setlocal filetype=ladder |
      \ elseif getline(1) =~# '^LDmicro' | setlocal filetype=ldmicro | endif
autocmd BufRead,BufNewFile *.txt,*.TXT
      \ if getline(1) =~# '^LDmicro export text' | setlocal filetype=ladder | endif
