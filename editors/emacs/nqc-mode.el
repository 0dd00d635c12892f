;;; nqc-mode.el --- NQC (LEGO RCX) editing with rcxc  -*- lexical-binding: t; -*-

;; A major mode for NQC built on c-mode: NQC keywords and the RCX API
;; highlighted, `M-x compile' running `rcxc compile' (its gcc-style messages
;; are what compilation-mode already reads), and rcxc's language server
;; registered for eglot.  See docs/editors.md.
;;
;; Install: put this file on your load-path, then
;;   (require 'nqc-mode)
;; and for the language server:  M-x eglot  in an NQC buffer.

;;; Code:

(require 'cc-mode)
(require 'compile)

(defgroup nqc nil "NQC for the LEGO RCX, compiled with rcxc." :group 'languages)

(defcustom nqc-rcxc-program "rcxc"
  "The rcxc executable."
  :type 'string :group 'nqc)

(defconst nqc-keywords
  '("task" "sub" "void" "int" "const" "inline" "if" "else" "while" "do" "until" "for" "repeat"
    "switch" "case" "default" "break" "continue" "return" "goto" "start" "stop" "asm"
    "true" "false" "__source" "__source_arg"))

;; The API of rcxc's stdlib/rcx.nqh (tests/lsp/editors_test.cpp checks it).
(defconst nqc-api-functions
  '("SetOutput" "SetDirection" "SetPower" "On" "Off" "Float" "Fwd" "Rev" "Toggle" "OnFwd"
    "OnRev" "Wait" "OnFor" "ClearTimer" "OutputStatus" "UploadDatalog" "SetWatch" "SetSensorType" "SetSensorMode" "SetSensor"
    "ClearSensor" "PlaySound" "PlayTone" "SelectDisplay" "ClearMessage" "SendMessage"
    "SetTxPower" "CreateDatalog" "AddToDatalog" "SetSleepTime" "SleepNow" "StopAllTasks" "_init"
    "Timer" "Watch" "SensorValue" "SensorType" "SensorMode" "SensorValueRaw" "SensorValueBool"
    "Message" "Random" "Program"))

(defconst nqc-api-constants
  '("T1" "T2" "T3" "T4" "OUT_A" "OUT_B" "OUT_C" "OUT_AB" "OUT_AC" "OUT_BC" "OUT_ABC" "OUT_FLOAT" "OUT_OFF"
    "OUT_ON" "OUT_REV" "OUT_TOGGLE" "OUT_FWD" "OUT_LOW" "OUT_HALF" "OUT_FULL" "SENSOR_1"
    "SENSOR_2" "SENSOR_3" "S1" "S2" "S3" "SENSOR_TYPE_NONE" "SENSOR_TYPE_TOUCH"
    "SENSOR_TYPE_TEMPERATURE" "SENSOR_TYPE_LIGHT" "SENSOR_TYPE_ROTATION" "SENSOR_MODE_RAW"
    "SENSOR_MODE_BOOL" "SENSOR_MODE_EDGE" "SENSOR_MODE_PULSE" "SENSOR_MODE_PERCENT"
    "SENSOR_MODE_CELSIUS" "SENSOR_MODE_FAHRENHEIT" "SENSOR_MODE_ROTATION" "SENSOR_TOUCH"
    "SENSOR_LIGHT" "SENSOR_ROTATION" "SENSOR_CELSIUS" "SENSOR_FAHRENHEIT" "SENSOR_PULSE"
    "SENSOR_EDGE" "_SENSOR_CFG" "SOUND_CLICK" "SOUND_DOUBLE_BEEP" "SOUND_DOWN" "SOUND_UP" "SOUND_LOW_BEEP"
    "SOUND_FAST_UP" "DISPLAY_WATCH" "DISPLAY_SENSOR_1" "DISPLAY_SENSOR_2" "DISPLAY_SENSOR_3"
    "DISPLAY_OUT_A" "DISPLAY_OUT_B" "DISPLAY_OUT_C" "TX_POWER_LO" "TX_POWER_HI"))

(defconst nqc-font-lock-keywords
  `((,(regexp-opt nqc-keywords 'symbols) . font-lock-keyword-face)
    (,(regexp-opt nqc-api-functions 'symbols) . font-lock-builtin-face)
    (,(regexp-opt nqc-api-constants 'symbols) . font-lock-constant-face)
    ("^\\s-*#\\s-*\\(define\\|undef\\|include\\|ifn?def\\|if\\|elif\\|else\\|endif\\|error\\|pragma\\)\\_>"
     . font-lock-preprocessor-face)
    ("\\_<\\(task\\|sub\\|void\\)\\s-+\\(\\(?:\\sw\\|\\s_\\)+\\)\\s-*(" 2 font-lock-function-name-face)
    ("//\\s-*\\(@[a-z-]+\\)" 1 font-lock-doc-face t)))

;;;###autoload
(define-derived-mode nqc-mode c-mode "NQC"
  "Major mode for NQC programs for the LEGO RCX, compiled by rcxc."
  (font-lock-add-keywords nil nqc-font-lock-keywords)
  (setq-local comment-start "// ")
  (setq-local comment-end "")
  (setq-local compile-command
              (concat nqc-rcxc-program " compile "
                      (if buffer-file-name (shell-quote-argument (file-name-nondirectory buffer-file-name)) ""))))

(defun nqc-run ()
  "Run the current program on rcxc's emulator."
  (interactive)
  (compile (concat nqc-rcxc-program " run " (shell-quote-argument buffer-file-name))))

(defun nqc-test ()
  "Check the current program's // @expect lines with rcxc test."
  (interactive)
  (compile (concat nqc-rcxc-program " test " (shell-quote-argument buffer-file-name))))

(defun nqc-download ()
  "Download the current program into the RCX and run it."
  (interactive)
  (compile (concat nqc-rcxc-program " download " (shell-quote-argument buffer-file-name) " --run")))

(define-key nqc-mode-map (kbd "C-c C-c") #'compile)
(define-key nqc-mode-map (kbd "C-c C-r") #'nqc-run)
(define-key nqc-mode-map (kbd "C-c C-t") #'nqc-test)
(define-key nqc-mode-map (kbd "C-c C-d") #'nqc-download)

;;;###autoload
(add-to-list 'auto-mode-alist '("\\.nq[ch]\\'" . nqc-mode))

(with-eval-after-load 'eglot
  (add-to-list 'eglot-server-programs `(nqc-mode ,nqc-rcxc-program "lsp")))

(provide 'nqc-mode)
;;; nqc-mode.el ends here
